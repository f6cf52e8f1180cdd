#pragma once
// Scene files: a readable, versioned JSON document (*.rpscene, rpSceneFile.h) that lists the
// nodes with their fields, attributes and references, and names one data file per node in a
// standard format (NRRD, .seg.nrrd, VTP, .mrk.json, ITK .tfm) in the same folder.
//
// Saving over a scene file keeps its data files' names and replaces their content; a file of the
// folder the previous scene did not write is never touched (the node takes another name), and
// the previous scene's files the new one no longer names are removed (rpSceneDataFiles.h). A save
// killed at any point, or one that fails (a full disk), leaves a scene file that loads whole: the
// previous scene, or the new one. Loading a scene whose data file is missing or corrupt loads
// everything else and reports each problem by file and node name.
#include <string>
#include <vector>

#include "rpSceneFile.h"

class vtkRPScene;

namespace rp {

struct SceneLoadReport {
  bool Ok = true;            // false: the scene file itself could not be read (nothing loaded)
  std::string Error;         // why, when !Ok
  int NodesLoaded = 0;
  std::vector<std::string> Problems;  // one line per node skipped: "<file> (<node name>): reason"
};

/// Writes `scene` to `sceneFile` and its data files beside it. Returns false and sets `error`
/// (the previous scene file, if any, is then intact).
bool SaveScene(vtkRPScene* scene, const std::string& sceneFile, std::string& error);

/// Imports the scene file into `scene` (IDs remapped if they clash; existing nodes are kept).
SceneLoadReport LoadScene(vtkRPScene* scene, const std::string& sceneFile);

}  // namespace rp

#pragma once
// Scene files: a readable, versioned JSON document (*.rpscene, rpSceneFile.h) that lists the
// nodes with their fields, attributes and references, and names one data file per node in a
// standard format (NRRD, .seg.nrrd, VTP, .mrk.json, ITK .tfm) in the same folder.
//
// Saving never touches what the previous version of the scene file uses: data files go to names
// the previous scene does not reference (CT.nrrd, then CT_2.nrrd, then CT.nrrd again...), the
// scene file is replaced last by an atomic rename (the commit), and only then are the previous
// version's data files that the new one no longer names removed. A save killed at any point, or
// one that fails (a full disk), leaves the previous scene loading intact. Loading a scene whose
// data file is missing or corrupt loads everything else and reports each problem by file and
// node name.
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

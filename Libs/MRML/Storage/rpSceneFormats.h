#pragma once
// Scene files of every format RoboPlan reads and writes, chosen by extension: our own .rpscene
// (rpSceneIO.h) and 3D Slicer's .mrml and .mrb (rpMrmlScene.h). What `roboplan convert` uses
// for scenes and the viewer uses to open and save them; the report is the same for all three.
#include <iosfwd>
#include <string>
#include <vector>

#include "rpMrmlScene.h"

class vtkRPScene;

namespace rp {

/// The scene file extensions (".rpscene", ".mrml", ".mrb").
const std::vector<std::string>& SceneFileExtensions();
/// True when `path` ends with one of them (case-insensitive).
bool IsSceneFileName(const std::string& path);

/// Reads a scene file of any of those formats into `scene` (added to; nothing there is lost).
bool ReadSceneFile(const std::string& path, vtkRPScene* scene, SceneTransferReport& report);
/// Writes `scene` in the format of `path`'s extension.
bool WriteSceneFile(vtkRPScene* scene, const std::string& path, SceneTransferReport& report);

/// A scene file converted to another format: what was read and written, or the first thing that
/// could not be done (a scene that cannot be read or written; a node left out for a missing or
/// unreadable data file; the output then holds everything else).
struct SceneConversion {
  bool DidRead = false, DidWrite = false;
  SceneTransferReport Read, Written;
  std::string Error;  // empty: converted whole
};
SceneConversion ConvertScene(const std::string& input, const std::string& output);

/// `roboplan convert <in> <out> [--json]`'s report of a scene conversion: what was read and
/// written (with --json one document: {"ok", "input", "output", "error"?, "read": {"format",
/// "nodes": {tag: count}, "files", "skipped": [{"what", "why"}], "warnings"}, "written": {...}}).
/// Returns the exit code: 0, or 1 with the error on `err`.
int ReportSceneConversion(const SceneConversion& conversion, const std::string& input, const std::string& output,
                          bool json, std::ostream& out, std::ostream& err);

/// ConvertScene, then ReportSceneConversion.
int ConvertSceneFile(const std::string& input, const std::string& output, bool json, std::ostream& out,
                     std::ostream& err);

}  // namespace rp

#pragma once
// The scene file's text (*.rpscene, versioned JSON) to plain data and back, without VTK: what
// LoadScene/SaveScene build nodes from and write, and what the scene fuzzer feeds arbitrary
// bytes. Parsing never throws: a malformed node entry is kept with the reason in Problem (the
// loader reports it and skips the node); a malformed document is an error.
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rp {

constexpr int SceneFileFormatVersion = 1;
constexpr const char* SceneFileExtension = ".rpscene";

struct SceneFileNode {
  std::string Class, ID, Name;
  std::map<std::string, std::string> Properties, Attributes;
  std::vector<std::pair<std::string, std::vector<std::string>>> References;  // role → node IDs
  std::string DataFile;  // beside the scene file; empty: the node has none
  std::string Problem;   // non-empty: the entry is malformed (why); the node is skipped
};

struct SceneFileDocument {
  int Version = SceneFileFormatVersion;
  std::vector<SceneFileNode> Nodes;
  // Files in the scene's folder it owns besides its nodes' data files: only a save that was
  // interrupted lists any (those it was replacing); the next save replaces or removes them
  // (rpSceneDataFiles.h). Written as "ownedFiles" only when not empty.
  std::vector<std::string> OwnedFiles;
};

/// Parses a scene file's text. False (and `error`, naming `source`) when it is not a RoboPlan
/// scene of a version this program reads.
bool ParseSceneFile(const std::string& text, const std::string& source, SceneFileDocument& document,
                    std::string& error);
/// The scene file's text for `document`.
std::string FormatSceneFile(const SceneFileDocument& document);

}  // namespace rp

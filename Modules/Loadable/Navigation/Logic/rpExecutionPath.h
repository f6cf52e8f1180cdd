#pragma once
// The tool path of an execution, read for scoring (rpExecutionScore.h) from what users have:
//   - a drilling recording (`roboplan drill --record`): the burr centre (the proxy: where the burr
//     cut) of every tick the burr ran, and the burr's radius;
//   - a PLUS tracked-frame sequence (`.igs.mha`, `.igs.nrrd`, ...) with the transform to follow
//     (e.g. StylusTipToReference): every frame's transforms are the live links of a transform
//     repository, a PLUS configuration's CoordinateDefinitions (e.g. StylusTipToStylus, and a
//     ReferenceToRAS from a registration) its fixed ones, so any name they connect can be
//     followed, as PLUS's repository does; frames where it is not valid are skipped and counted;
//   - a CSV with the header `R,A,S`: one tool-tip point per row (mm, RAS), in the order drilled.
// The points are in the plan's frame only if the file's are: name the transform that ends there.
#include <string>
#include <vector>

#include "rpVec3.h"

namespace rp {

struct ExecutionPathOptions {
  std::string Transform;      // PLUS sequences: the transform to follow, "<From>To<To>"
  std::string Configuration;  // PLUS sequences: a PLUS configuration whose CoordinateDefinitions add fixed transforms
};

struct ExecutionPath {
  std::string Kind;              // "drill-recording", "plus-sequence", "csv"
  std::vector<Vec3> Points;      // in the order drilled
  double ToolRadiusMm = 0;       // a drilling recording's burr (0 when the file does not say)
  size_t Samples = 0;            // rows, ticks or frames in the file
  size_t Skipped = 0;            // of those, not used (burr off; transform not valid)
  std::string Chain;             // PLUS: how the transform was composed
};

/// False with `error` naming the file and the problem (unknown format, no such transform, a bad row).
bool ReadExecutionPath(const std::string& file, const ExecutionPathOptions& options, ExecutionPath& path,
                       std::string& error);

/// The transforms a PLUS sequence can be followed through (with the configuration's fixed ones):
/// every connected frame pair "<From>To<To>", those from a tool tip first (what a score follows).
/// Empty for a file that is not a PLUS sequence. False with `error` naming the file.
bool ListPathTransforms(const std::string& file, const std::string& configuration, std::vector<std::string>& names,
                        std::string& error);

}  // namespace rp

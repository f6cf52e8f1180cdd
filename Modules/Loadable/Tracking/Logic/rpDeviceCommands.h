#pragma once
// The device side of issue 27 in the CLI, kept apart from rpTrackingCommands.cxx so that the
// two halves merge cleanly:
//   roboplan tool-info <file.rom|tool.json> [--json] [--write OUT.rom]   (NDI tool definitions)
//   roboplan track --plus-config PlusDeviceSet_X.xml [--plus-config-dir DIR] [--check] ...
// PreparePlusTrack reads the configuration and, unless --check (which prints what would be set
// up and what is refused, opening no device), makes the pose source and the transform relay
// that RunTrackCommand then runs and serves.
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "rpPlusConfiguration.h"
#include "rpPlusTracking.h"
#include "rpPoseSource.h"

namespace rp {

class ArgParser;

int RunToolInfoCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

/// What `track --plus-config` sets up.
struct PlusTrack {
  plus::Configuration Configuration;
  PoseSourceConfig Config;               // kind and address, for the report
  std::unique_ptr<PoseSource> Source;
  std::unique_ptr<PlusTransformRelay> Relay;
  std::shared_ptr<PlusTransformRelay> Commands;  // the server thread's: GetTransform/UpdateTransform
  int ServePort = -1;                    // ListeningPort (-1: no server section)
  std::string ListeningAddress;          // the section's ListeningAddress (ours; "" when not given)
  bool SendInvalid = false;              // !SendValidTransformsOnly
  double KeepAliveSeconds = 0.25;
};

/// Adds --plus-config, --plus-config-dir, --check to the track command's options.
void AddPlusTrackOptions(ArgParser& parser);
/// -1: go on tracking with `plan`; otherwise the exit code (--check done: 0 when a tracker of the
/// file can run, 1 when none can; or an error printed).
int PreparePlusTrack(const ArgParser& parser, PlusTrack& plan, std::ostream& out, std::ostream& err);

}  // namespace rp

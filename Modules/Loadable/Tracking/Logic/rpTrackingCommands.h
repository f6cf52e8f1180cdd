#pragma once
// CLI subcommands of the Tracking module (testable without the host):
//   roboplan track --serial <port> | --igtl <host:port> | --replay <file> | --simulate | --source <kind>
//                  [--rom <file> ...] [--seconds N] [--record <file>] [--serve <port>] [--json]
//   roboplan pivot <recording> [--tool NAME] [--reference NAME] [--threshold MM] [--json]
//   roboplan polaris-sim [--port-link <path>] [--tool <json> ...] [--rate 20|60] ...
#include <atomic>
#include <ostream>
#include <string>
#include <vector>

class vtkRPScene;

namespace rp {

int RunTrackCommand(const std::vector<std::string>& args, vtkRPScene* scene, std::ostream& out, std::ostream& err);
int RunPivotCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
/// Runs until `stop` becomes true, --seconds elapse, or SIGINT/SIGTERM.
int RunPolarisSimCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                         const std::atomic<bool>* stop = nullptr);

}  // namespace rp

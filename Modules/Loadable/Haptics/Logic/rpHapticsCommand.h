#pragma once
// `roboplan haptics ...`: the Haptics module's CLI, here (not in the plugin) so tests can run it
// in-process. Touches the scene's haptic models with the simulated device along a scripted
// trajectory at 1 kHz and prints servo timing, force statistics and the tissues the device
// clamps.
#include <ostream>
#include <string>
#include <vector>

class vtkRPScene;

namespace rp {

/// Returns the exit code: 0 done, 1 the work failed (reason on `err`), 2 bad arguments.
/// `scene` may be null (a scene of its own is used).
int RunHapticsCommand(const std::vector<std::string>& arguments, vtkRPScene* scene, std::ostream& out,
                      std::ostream& err);

}  // namespace rp

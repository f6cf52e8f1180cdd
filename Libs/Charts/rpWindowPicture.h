#pragma once
// A rendered window as a PNG (libRoboPlanChartsDraw.so: link RoboPlanChartsDraw to call it; code
// that renders its own pictures lives in a library loaded when a command draws, see Libs/Charts).
#include <string>

class vtkRenderWindow;

namespace rp::bench {

/// Renders an offscreen window and writes what it shows as a PNG (charts, pictures). Without an X
/// display (rp::EnsureXDisplay) it returns false naming why and renders nothing.
bool WriteWindowPNG(vtkRenderWindow* window, const std::string& path, std::string& error);

}  // namespace rp::bench

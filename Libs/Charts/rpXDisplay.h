#pragma once
// An X display for offscreen pictures (charts, screenshots), and the one connection to it that
// every offscreen render window of the process shares.
//
// Debian's VTK 9.1 renders through GLX only (no EGL or OSMesa build), so even an offscreen render
// window needs an X connection. Left to itself, each VTK window opens its own with XOpenDisplay and
// calls abort() when that fails ("bad X server connection ... Aborting."), and closes it when the
// window goes. An X server started without -noreset (xvfb-run's, a plain `Xvfb :N`) resets when
// its last client disconnects, and refuses connections while it resets (a loop that connects and
// disconnects had 15 % of its connections refused). The old probe here opened and closed the
// display just before VTK opened its own, and each picture's window closed the last connection
// before the next one opened: the demo, which draws a dozen pictures, died in a third of its runs.
//
// So: EnsureXDisplay() opens the display once (retrying for a few seconds while a server resets,
// which another client's departure can cause at any time) and keeps that connection open until the
// process exits, so the server never sees its last client leave while this process works; and
// PrepareOffscreenWindow() hands that connection to every window before its first Render(), so VTK
// never opens one of its own and never aborts. Without $DISPLAY, or when $DISPLAY cannot be opened,
// it starts a private Xvfb for this process (Xvfb picks a free display itself with -displayfd,
// screen 1920x1080x24, -noreset), sets $DISPLAY to it and stops it when the process exits. Where
// neither works it returns false with the reason, and the caller skips its picture with a named
// warning: a picture that cannot be drawn never costs the figures computed before it.
#include <string>

class vtkRenderWindow;

namespace rp {

struct XDisplayInfo {
  std::string Name;              // ":0", ":42"; empty when there is none
  int Width = 0, Height = 0;     // of the default screen, pixels
  int Depth = 0;                 // of the default screen, bits
  bool Private = false;          // started by EnsureXDisplay for this process
  std::string Refused;           // why $DISPLAY was not used when it was set (then Private is true)
};

/// True when an X display for offscreen rendering is open to this process (see above). Thread-safe;
/// the display is looked for once and the private Xvfb started at most once. Calls XInitThreads()
/// first (windows may render on several threads through the one connection), so it must come
/// before any other Xlib call of the process; Qt, which opens its own connection, calls it too.
/// `error` names why there is none.
bool EnsureXDisplay(std::string& error);

/// Readies `window` for offscreen drawing on the display above, through the process's one
/// connection (see above). Call it after making the window and before its first Render(); false
/// with `error` (naming the display problem) when there is no display, and the window must then not
/// be rendered.
bool PrepareOffscreenWindow(vtkRenderWindow* window, std::string& error);

/// The display EnsureXDisplay found (its name, screen size and depth); empty when it found none or
/// was not called.
XDisplayInfo CurrentXDisplay();

}  // namespace rp

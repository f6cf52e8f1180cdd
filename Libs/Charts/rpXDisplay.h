#pragma once
// An X display for offscreen pictures (charts, screenshots) on a machine without one.
//
// Debian's VTK 9.1 renders through GLX only (no EGL or OSMesa build), so even an offscreen render
// window opens an X connection, and without one VTK's X render window dies in XSync (SIGSEGV).
// EnsureXDisplay() is called before any window is made: it uses $DISPLAY when that display opens;
// without $DISPLAY it starts a private Xvfb for this process, the way the tests' run-with-xvfb.sh
// does (Xvfb picks a free display itself with -displayfd, screen 1920x1080x24), sets $DISPLAY to
// it and stops it when the process exits. Where neither works it returns false with the reason,
// and the caller skips its picture with a named warning: a picture that cannot be drawn never
// costs the figures computed before it.
#include <string>

namespace rp {

struct XDisplayInfo {
  std::string Name;              // ":0", ":42"; empty when there is none
  int Width = 0, Height = 0;     // of the default screen, pixels
  int Depth = 0;                 // of the default screen, bits
  bool Private = false;          // started by EnsureXDisplay for this process
};

/// True when an X display for offscreen rendering is open to this process (see above). Thread-safe;
/// the private Xvfb is started at most once. `error` names why there is none.
bool EnsureXDisplay(std::string& error);

/// The display EnsureXDisplay found (its name, screen size and depth); empty when it found none or
/// was not called.
XDisplayInfo CurrentXDisplay();

}  // namespace rp

// Headless rendering: Debian's VTK is a GLX build, so with no DISPLAY a
// private Xvfb (Mesa llvmpipe) is started for this process and stopped at
// exit. No X library calls: only a child process and the DISPLAY variable,
// so OSMesa/EGL builds of VTK need none of this (DISPLAY is then ignored).
#ifndef ssHeadless_h
#define ssHeadless_h

#include <string>

namespace ssapp
{
class PrivateDisplay
{
public:
  PrivateDisplay() = default;
  ~PrivateDisplay();
  PrivateDisplay(const PrivateDisplay&) = delete;
  PrivateDisplay& operator=(const PrivateDisplay&) = delete;

  /// Starts Xvfb when DISPLAY is unset. Returns false with a message when an
  /// X server is needed but cannot be started.
  bool EnsureDisplay(std::string& message);
  void Stop();

private:
  int Pid = -1;
};
}

#endif

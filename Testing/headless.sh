#!/bin/sh
# Runs a command with an X display: Debian's VTK/ParaView are GLX builds, so
# when no display is set, a private Xvfb (Mesa llvmpipe) is started for it.
if [ -n "${DISPLAY:-}" ]; then
  exec "$@"
fi
exec xvfb-run -a -s "-screen 0 1600x1200x24 -nolisten tcp" "$@"

#!/usr/bin/env bash
# Runs a command with an X display: Debian's VTK/ParaView are GLX builds, so
# when no display is set, a private Xvfb (Mesa llvmpipe) is started for it.
# Xvfb picks a free display itself (-displayfd), so parallel tests do not race
# the way `xvfb-run -a` does.
if [ -n "${DISPLAY:-}" ]; then
  exec "$@"
fi
tmp=$(mktemp)
Xvfb -displayfd 3 -screen 0 1600x1200x24 -nolisten tcp 3>"$tmp" >/dev/null 2>&1 &
xpid=$!
for _ in $(seq 1 200); do
  [ -s "$tmp" ] && break
  if ! kill -0 "$xpid" 2>/dev/null; then break; fi
  sleep 0.05
done
if [ ! -s "$tmp" ]; then
  echo "headless.sh: could not start Xvfb" >&2
  kill "$xpid" 2>/dev/null
  rm -f "$tmp"
  exit 1
fi
num=$(head -n1 "$tmp" | tr -d '[:space:]')
rm -f "$tmp"
export DISPLAY=":$num"
# the server is up when its socket exists
for _ in $(seq 1 100); do
  [ -S "/tmp/.X11-unix/X$num" ] && break
  sleep 0.05
done
"$@"
rc=$?
kill "$xpid" 2>/dev/null
wait "$xpid" 2>/dev/null
exit $rc

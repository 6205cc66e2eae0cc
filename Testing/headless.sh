#!/usr/bin/env bash
# Runs a command with an X display: Debian's VTK/ParaView are GLX builds, so
# when no display is set, a private Xvfb (Mesa llvmpipe) is started for it.
# The display number is random in a high range, not "the lowest free one":
# when one test's Xvfb exits just as another starts on the number it freed,
# the exiting server can unlink the new one's socket. -noreset: by default an
# X server resets when its last client disconnects and refuses connections
# meanwhile, which made the next render window of a test fail now and then.
if [ -n "${DISPLAY:-}" ]; then
  exec "$@"
fi
xpid=""
for _ in $(seq 1 20); do
  num=$(( 200 + (RANDOM * 32768 + RANDOM) % 30000 ))
  [ -e "/tmp/.X${num}-lock" ] && continue
  Xvfb ":$num" -screen 0 1600x1200x24 -nolisten tcp -noreset >/dev/null 2>&1 &
  xpid=$!
  # ready when its socket accepts a connection (the file appears before
  # the server listens)
  ready=0
  for _ in $(seq 1 200); do
    kill -0 "$xpid" 2>/dev/null || break
    if [ -S "/tmp/.X11-unix/X$num" ] && /usr/bin/python3 -c "import socket,sys; s=socket.socket(socket.AF_UNIX); s.connect(sys.argv[1])" "/tmp/.X11-unix/X$num" 2>/dev/null; then
      ready=1
      break
    fi
    sleep 0.05
  done
  if [ "$ready" = 1 ]; then
    break
  fi
  kill "$xpid" 2>/dev/null
  wait "$xpid" 2>/dev/null
  xpid=""
done
if [ -z "$xpid" ]; then
  echo "headless.sh: could not start Xvfb" >&2
  exit 1
fi
export DISPLAY=":$num"
"$@"
rc=$?
kill "$xpid" 2>/dev/null
wait "$xpid" 2>/dev/null
exit $rc

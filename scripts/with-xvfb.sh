#!/bin/bash
# Runs a command under its own Xvfb and returns the command's exit status.
#
#   scripts/with-xvfb.sh COMMAND [ARG...]
#
# Why not `xvfb-run -a`: its X server resets when the last client disconnects, and ParaView
# opens and closes a probe connection before its real one; under load the real one can arrive
# during the reset and be refused ("bad X server connection": once in CI on :160, and in 3 of 4
# concurrent local pvpython runs). This script starts Xvfb with -noreset (measured: 12 of 12
# concurrent runs then pass), on a random display number in 1000..9999 whose lock file is free
# (away from the low numbers other tools probe), and waits until the server reports it is ready
# (-displayfd); a taken number is retried with another.
set -u
if [ $# -eq 0 ]; then
  echo "usage: $0 COMMAND [ARG...]" >&2
  exit 2
fi
command -v Xvfb >/dev/null || { echo "$0: Xvfb not found (Debian package xvfb)" >&2; exit 2; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/ddg-xvfb.XXXXXX")
xvfb_pid=""
cleanup() {
  if [ -n "$xvfb_pid" ]; then
    kill "$xvfb_pid" 2>/dev/null
    wait "$xvfb_pid" 2>/dev/null
  fi
  rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# -noreset: an X server resets when its last client disconnects, and ParaView opens and closes a
# probe connection before its real one; a connection arriving during the reset is refused
# ("Invalid MIT-MAGIC-COOKIE-1 key" / "Authorization required", then "bad X server connection":
# 3 of 4 concurrent pvpython runs under load). No access control (-ac): the server listens on
# local sockets only (-nolisten tcp) and lives for one test.
mkfifo "$tmp/display"
display=""
for attempt in 1 2 3 4 5 6 7 8; do
  n=$((1000 + (RANDOM * 32768 + RANDOM) % 9000))
  [ -e "/tmp/.X$n-lock" ] && continue
  Xvfb ":$n" -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -ac -noreset \
    3>"$tmp/display" >"$tmp/log" 2>&1 &
  xvfb_pid=$!
  read -r -t 60 display <"$tmp/display" || true
  if [ -n "$display" ] && kill -0 "$xvfb_pid" 2>/dev/null; then
    break
  fi
  kill "$xvfb_pid" 2>/dev/null
  wait "$xvfb_pid" 2>/dev/null
  xvfb_pid=""
  display=""
done
if [ -z "$display" ]; then
  echo "$0: Xvfb did not start; its last log:" >&2
  cat "$tmp/log" >&2
  exit 2
fi
export DISPLAY=":$display"
unset XAUTHORITY
"$@"

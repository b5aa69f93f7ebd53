#!/bin/bash
# Runs a command under its own Xvfb and returns the command's exit status.
#
#   scripts/with-xvfb.sh COMMAND [ARG...]
#
# Why not `xvfb-run -a`: it picks the first display number without a /tmp/.X<N>-lock file, but
# X sockets also live in Linux's abstract namespace, which is per network namespace, not per
# /tmp. On a machine where another container shares the network namespace and runs an X server
# on that number, our Xvfb loses the abstract socket and the client connects to the other
# server ("bad X server connection"). With -displayfd the X server itself tries display numbers
# until it owns the lock file and every socket, then writes the number it took.
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

# A cookie in a private authority file. The server loads every MIT-MAGIC-COOKIE-1 in its -auth
# file whatever display the entry names, so the cookie goes in before the number is known (as
# display 0); the client entry for the display actually taken is added once it is known.
cookie=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
touch "$tmp/auth"
xauth -q -f "$tmp/auth" add :0 . "$cookie"
mkfifo "$tmp/display"
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -auth "$tmp/auth" \
  3>"$tmp/display" >"$tmp/log" 2>&1 &
xvfb_pid=$!
display=""
read -r -t 60 display <"$tmp/display" || true
if [ -z "$display" ]; then
  echo "$0: Xvfb did not start; its log:" >&2
  cat "$tmp/log" >&2
  exit 2
fi
xauth -q -f "$tmp/auth" add ":$display" . "$cookie"
export DISPLAY=":$display"
export XAUTHORITY="$tmp/auth"
"$@"

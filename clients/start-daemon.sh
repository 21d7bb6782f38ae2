# Sourced by clients/run-interop.sh and bench/run-load: start `VPROF serve --port 0` with its
# stderr in LOG, wait for its `listening on 127.0.0.1:PORT` line (up to 10 s), and set `pid`
# and `port`; on failure print the log and return 1. The caller stops the daemon (kill $pid).
#
#   start_daemon VPROF LOG
start_daemon() {
  "$1" serve --port 0 2>"$2" &
  pid=$!
  for _ in $(seq 100); do grep -q "listening on" "$2" && break; sleep 0.1; done
  port="$(sed -n 's/.*listening on [0-9.]*:\([0-9]*\).*/\1/p' "$2" | head -1)"
  [ -n "$port" ] || { echo "the daemon did not start"; cat "$2"; return 1; }
}

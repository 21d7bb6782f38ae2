#!/usr/bin/env bash
# Interop of vprof serve with the Python and C++ clients.
#
#   clients/run-interop.sh [PATH_TO_VPROF]
#
# Builds the C++ client, generates the Python code, starts `PATH_TO_VPROF serve --port 0`
# (it prints `listening on 127.0.0.1:PORT` on stderr), runs both clients over every
# example (examples/*.pb, or requests made from the reference JSON when there are none),
# runs the Python client tests, stops the daemon with SIGTERM (it must exit 0), and exits
# non-zero on any failure.
#
# PATH_TO_VPROF defaults to `stack exec -- which vprof`. With the stub daemon
# (vprof-stub-daemon, no generator) set VPROF_STUB=1: the clients then check the exchange
# only, not the profiles (those checks need the real generator).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
vprof="${1:-$(cd "$root" && stack exec -- which vprof)}"
shared="${VPROF_SHARED:-$root/../shared}"
cases="${VPROF_CASES:-$shared/reference/velocity-cases.json}"
cases="$(cd "$(dirname "$cases")" && pwd)/$(basename "$cases")"
stub="${VPROF_STUB:-0}"
tmp="$(mktemp -d)"
pid=""
cleanup() { [ -n "$pid" ] && kill -TERM "$pid" 2>/dev/null || true; rm -rf "$tmp"; }
trap cleanup EXIT

make -s -C "$here/cpp"
python3 -c "import sys; sys.path.insert(0, '$here/python'); import vprof_client._gen as g; g.generate(force=True)"

shopt -s nullglob
examples=("$root"/examples/*.pb)
if [ ${#examples[@]} -eq 0 ]; then
  python3 "$here/make_examples.py" "$cases" "$tmp/examples" >/dev/null
  examples=("$tmp"/examples/*.pb)
  json="$cases"
else
  json="$cases"
fi

. "$here/start-daemon.sh"
start_daemon "$vprof" "$tmp/daemon.log"
echo "daemon $vprof on port $port"

status=0
only=()
[ "$stub" = 1 ] && only=(--transport-only)
echo "== C++ client (${#examples[@]} examples)"
"$here/cpp/build/vprof_check" --port "$port" "${only[@]}" "${examples[@]}" || status=1
echo "== Python client"
(cd "$here/python" && python3 -m vprof_client "$json" --port "$port" "${only[@]}") || status=1
echo "== Python client over --stdio"
(cd "$here/python" && python3 -m vprof_client "$json" --spawn "$vprof" --case simple "${only[@]}") || status=1
if [ "$stub" != 1 ]; then
  echo "== FK and IK: Python and C++ examples, responses compared byte for byte"
  python3 "$here/python/kinematics_example.py" --port "$port" --out "$tmp/kin-py.bin" || status=1
  "$here/cpp/build/vprof_kinematics" --port "$port" --out "$tmp/kin-cpp.bin" || status=1
  if cmp -s "$tmp/kin-py.bin" "$tmp/kin-cpp.bin"; then
    echo "kinematics responses identical ($(wc -c < "$tmp/kin-py.bin") bytes)"
  else
    echo "kinematics responses differ between the Python and the C++ client"; status=1
  fi
  echo "== Robot selection: Python and C++ examples, responses compared byte for byte"
  python3 "$here/python/select_example.py" --port "$port" --out "$tmp/sel-py.bin" || status=1
  "$here/cpp/build/vprof_select" --port "$port" --out "$tmp/sel-cpp.bin" || status=1
  if cmp -s "$tmp/sel-py.bin" "$tmp/sel-cpp.bin"; then
    echo "selection responses identical ($(wc -c < "$tmp/sel-py.bin") bytes)"
  else
    echo "selection responses differ between the Python and the C++ client"; status=1
  fi
  echo "== Path planning: Python and C++ examples, responses compared byte for byte"
  python3 "$here/python/plan_example.py" --port "$port" --out "$tmp/plan-py.bin" || status=1
  "$here/cpp/build/vprof_plan" --port "$port" --square "$root/examples/plan-square.csv" --out "$tmp/plan-cpp.bin" || status=1
  if cmp -s "$tmp/plan-py.bin" "$tmp/plan-cpp.bin"; then
    echo "plan responses identical ($(wc -c < "$tmp/plan-py.bin") bytes)"
  else
    echo "plan responses differ between the Python and the C++ client"; status=1
  fi
  echo "== Path compression: Python and C++ examples, responses compared byte for byte"
  rec="$shared/data/freiburg1_xyz-groundtruth.txt"
  python3 "$here/python/compress_example.py" --port "$port" --recording "$rec" --out "$tmp/cmp-py.bin" || status=1
  "$here/cpp/build/vprof_compress" --port "$port" --recording "$rec" --out "$tmp/cmp-cpp.bin" || status=1
  if cmp -s "$tmp/cmp-py.bin" "$tmp/cmp-cpp.bin"; then
    echo "compression responses identical ($(wc -c < "$tmp/cmp-py.bin") bytes)"
  else
    echo "compression responses differ between the Python and the C++ client"; status=1
  fi
fi
echo "== C++ checker self test"
"$here/cpp/build/vprof_check" --selftest >/dev/null || { echo "checker self test failed"; status=1; }
echo "== Python client tests"
real=1; [ "$stub" = 1 ] && real=0
if VPROF_DAEMON="$vprof" VPROF_REAL="$real" VPROF_CASES="$cases" \
     python3 -W ignore::ResourceWarning -m unittest discover -s "$here/python/tests" 2>"$tmp/py.log"; then
  tail -3 "$tmp/py.log"
else
  grep -v '^vprof ' "$tmp/py.log"; status=1
fi

kill -TERM "$pid"
if wait "$pid"; then echo "daemon drained and exited 0"; else echo "daemon exit status $?"; status=1; fi
pid=""
grep -c '^vprof request_id=' "$tmp/daemon.log" | sed 's/^/daemon log lines: /'
[ $status = 0 ] && echo "interop: OK" || echo "interop: FAILED"
exit $status

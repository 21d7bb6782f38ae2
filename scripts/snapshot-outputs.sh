#!/usr/bin/env bash
# Write every example's outputs (profile CSV, table, JSON and summary without the compute
# time; compression paths and reports) into DIR, so that two builds can be compared
# byte for byte:  scripts/snapshot-outputs.sh DIR_A; (change, rebuild); scripts/snapshot-outputs.sh DIR_B; diff -r DIR_A DIR_B
set -euo pipefail
out=${1:?usage: snapshot-outputs.sh DIR}
cd "$(dirname "$0")/.."
shared=${VPROF_SHARED:-../shared}
mkdir -p "$out"
run() { stack exec vprof -- "$@"; }
for f in examples/*.json examples/*.pb; do
  n=$(basename "$f")
  run "$f" --format csv -o "$out/$n.csv" | grep -v '^compute time' > "$out/$n.summary" || true
  run "$f" --format table -o "$out/$n.table" > /dev/null || true
  run "$f" --format json 2>/dev/null | python3 -c 'import json,sys; d=json.load(sys.stdin); d.pop("compute_time",None); print(json.dumps(d,sort_keys=True))' > "$out/$n.jsonout" || true
done
for r in freiburg1_xyz-groundtruth.txt V101_gt.txt; do
  for fmt in tum mod csv; do
    run compress "$shared/data/$r" -o "$out/$r.$fmt" --output-format $fmt > /dev/null 2>&1 || true
  done
  run compress "$shared/data/$r" --report 2>&1 | grep -vi 'time' > "$out/$r.report" || true
  run compress "$shared/data/$r" --method rdp -o "$out/$r.rdp.tum" > /dev/null 2>&1 || true
done

#!/bin/sh
# Timing and quality table of path compression on both real recordings (the default knot fit,
# with RDP at the same number of points), then the criterion benchmark.
# Run from the project root:  sh bench/compress-report.sh
set -e
DATA=${VPROF_SHARED:+$VPROF_SHARED/data}
[ -n "$DATA" ] && [ -d "$DATA" ] || DATA=../shared/data
stack build
for f in freiburg1_xyz-groundtruth.txt V101_gt.txt; do
  echo "== $f"
  /usr/bin/env time -f "wall %e s (whole command: read, compress, RDP, metrics)" \
    stack exec vprof -- compress "$DATA/$f" --report
done
stack bench --benchmark-arguments '--match prefix compress'

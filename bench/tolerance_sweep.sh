#!/usr/bin/env bash
# What the function tolerance costs and buys: the claw drag of the 104K
# armadillo (30 frames) with each backend at function tolerances 1e-12 ... 1e-5,
# printing the median frame and how far the final vertices are from the
# 1e-12 result (max and RMS over the bounding-box diagonal).
#
#   bench/tolerance_sweep.sh [BUILD_DIR]      (default: build; about 2 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
MESH=data/meshes/armadillo_104k.off
test -f "$MESH" || { echo "missing $MESH (data/fetch_meshes.sh, msdeform_make_large)" >&2; exit 1; }
cmake --build "$BUILD" -j2 --target msdeform >/dev/null
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
echo "| solver | function tolerance | median frame ms | iterations | max / diag | rms / diag |"
echo "|---|---|---|---|---|---|"
for solver in ceres gauss_newton; do
  for tolerance in 1e-12 1e-8 1e-7 1e-6 1e-5; do
    "$BUILD/apps/msdeform" --mesh="$MESH" --solver=$solver --function_tolerance=$tolerance \
      --frames=30 --out="$OUT/$solver-$tolerance.off" --report="$OUT/$solver-$tolerance.json" --quiet
    distance=$(python3 bench/mesh_distance.py "$OUT/$solver-1e-12.off" "$OUT/$solver-$tolerance.off")
    python3 - "$OUT/$solver-$tolerance.json" "$solver" "$tolerance" "$distance" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
d = sys.argv[4].split()
print("| %s | %s | %.2f | %g | %s | %s |" % (sys.argv[2], sys.argv[3], r["timings_ms"]["frame_median"],
      r["solver"]["iterations_median"], d[1], d[3]))
PY
  done
done

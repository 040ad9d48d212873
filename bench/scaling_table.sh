#!/usr/bin/env bash
# Regenerates docs/performance_large.md and docs/images/scaling.png: how each
# fixed cost grows with the vertex count. The claw drag
# (data/scenarios/armadillo_claw.json, 30 frames, Gauss-Newton, 2 threads) on
# the armadillo at 26K, 104K, 416K (OFF text), 1.66M and 6.6M vertices (binary
# PLY, made by `msdeform_make_large --huge`, not committed): load, precompute
# (Init), layout change (rigidity, scale selection with the selected scale's
# skinning data, the solver's set-up), frame (solve, skin) medians from
# msdeform's report, whole-process peak memory from /usr/bin/time -v; and
# CGAL's ARAP (bench/cgal_arap_benchmark: Laplacian factorisation and one
# local/global iteration) up to 1.66M.
#
#   bench/scaling_table.sh [BUILD_DIR]      (default: build)
#
# About 6 minutes on a 2-core machine and 4.5 GB of memory at most (CGAL at
# 1.66M). Run it on a quiet machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
cmake --build "$BUILD" -j2 --target msdeform msdeform_make_large cgal_arap_benchmark >/dev/null
"$BUILD/apps/msdeform_make_large" --huge >/dev/null
source bench/table_common.sh
mkdir -p docs/images
uptime > "$OUT/load_before.txt"
for mesh in armadillo.off armadillo_104k.off armadillo_416k.off armadillo_1664k.ply \
            armadillo_6656k.ply; do
  name=${mesh%.*}
  timed_msdeform "$name" --scenario=data/scenarios/armadillo_claw.json \
    --mesh="data/meshes/$mesh" --solver=gauss_newton --threads=2 --frames=30 \
    --out="$OUT/$name.ply" --report="$OUT/$name.json" --quiet
  rm -f "$OUT/$name.ply"
done
"$BUILD/bench/cgal_arap_benchmark" --benchmark_format=json > "$OUT/cgal_arap.json" 2>/dev/null
uptime > "$OUT/load_after.txt"
/usr/bin/python3 bench/scaling_table.py "$OUT" docs/performance_large.md docs/images/scaling.png
echo "wrote docs/performance_large.md and docs/images/scaling.png"

#!/usr/bin/env bash
# Regenerates docs/performance.md: the claw drag (data/scenarios/armadillo_claw.json,
# 30 frames) on the 26K, 104K and 416K armadillo with msdeform for multiscale
# (each solver backend, 1 and 2 threads; and with a stiff handle, --w_con=10000),
# static (220 nodes) and static_dense,
# whole-process peak memory from /usr/bin/time -v, CGAL ARAP per iteration on
# the same handles (bench/cgal_arap_benchmark), and a perf profile of the
# 104K drag.
#
#   bench/performance_table.sh [BUILD_DIR]      (default: build)
#
# Takes about 10 minutes on a 2-core machine. Timings on a loaded machine are
# noisy (2-thread OpenMP suffers most); run it on a quiet machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
cmake --build "$BUILD" -j2 --target msdeform deformer_benchmark cgal_arap_benchmark >/dev/null
source bench/table_common.sh
uptime > "$OUT/load_before.txt"
for mesh in armadillo armadillo_104k armadillo_416k; do
  test -f "data/meshes/$mesh.off" || { echo "missing data/meshes/$mesh.off (data/fetch_meshes.sh, msdeform_make_large)" >&2; exit 1; }
  # method:solver:threads[:w_con]; a w_con other than Eq. 17's 100 is the stiff-handle run that
  # meets static_dense's handle error.
  for config in multiscale:ceres:2 multiscale:gauss_newton:2 multiscale:ceres:1 \
                multiscale:gauss_newton:1 multiscale:ceres:2:10000 multiscale:gauss_newton:2:10000 \
                static:ceres:2 static:gauss_newton:2 static_dense:ceres:2 static_dense:gauss_newton:2; do
    IFS=: read -r method solver threads w_con <<< "$config"
    label=$method
    extra=()  # msdeform's own default weight unless the config names one
    if [[ -n "$w_con" ]]; then
      label="$method-wcon$w_con"
      extra=(--w_con="$w_con")
    fi
    name="${mesh}__${label}__${solver}__${threads}"
    timed_msdeform "$name" --mesh="data/meshes/$mesh.off" --method="$method" \
      --solver="$solver" --threads="$threads" "${extra[@]}" --frames=30 \
      --out="$OUT/$name.off" --report="$OUT/$name.json" --quiet
    rm -f "$OUT/$name.off"
  done
done
"$BUILD/bench/cgal_arap_benchmark" --benchmark_filter=-1664k --benchmark_format=json > "$OUT/cgal_arap.json" 2>/dev/null
# Where the time goes: the 104K multiscale drag, each backend, 1 thread.
for solver in ceres gauss_newton; do
  perf record -q -g -o "$OUT/$solver.perf" "$BUILD/apps/msdeform" \
    --mesh=data/meshes/armadillo_104k.off --solver=$solver --threads=1 --frames=300 \
    --out="$OUT/profile_$solver.off" --report="$OUT/profile_$solver.json" --overwrite --quiet \
    >/dev/null
  perf report -i "$OUT/$solver.perf" --no-children --sort dso,symbol --stdio 2>/dev/null \
    | grep -E '^ +[0-9.]+%' | head -25 > "$OUT/$solver.profile" || true
done
uptime > "$OUT/load_after.txt"
python3 bench/performance_table.py "$OUT" > docs/performance.md.tmp
mv docs/performance.md.tmp docs/performance.md
echo "wrote docs/performance.md"

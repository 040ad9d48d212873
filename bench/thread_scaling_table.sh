#!/usr/bin/env bash
# Regenerates docs/performance_threads.md: how each stage of an edit scales
# with the thread count. The claw drag (data/scenarios/armadillo_claw.json, 30
# frames, the default solver) on the armadillo at 104K (OFF text), 1.66M and
# 6.66M vertices (binary PLY, made by `msdeform_make_large --huge`, not
# committed), on 1, 2 and all cores (`nproc`), each REPEATS times (default 3;
# the table takes medians), the thread counts of one repetition back to back
# so that they meet the same load. Every stage from msdeform's report
# (timings_ms and timings_ms.stages), whole-process peak memory from
# /usr/bin/time -v; bench/thread_scaling_table.py formats them, with the
# speedup, the parallel efficiency and Amdahl's serial fraction of each stage.
#
#   bench/thread_scaling_table.sh [BUILD_DIR]      (default: build)
#   REPEATS=1 PERF_OUT=/tmp/threads bench/thread_scaling_table.sh   (one run each, reports kept)
#
# Reports: $OUT/<mesh stem>_t<threads>_r<repetition>.json (bench/table_common.sh
# for $OUT). About 2 minutes on a 2-core machine at REPEATS=3, 2 GB of memory
# at most (6.66M). Run it on a quiet machine.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
REPEATS=${REPEATS:-3}
if ! [[ "$REPEATS" =~ ^[1-9][0-9]*$ ]]; then
  echo "thread_scaling_table.sh: REPEATS must be a positive whole number, not '$REPEATS'" >&2
  exit 1
fi
cmake --build "$BUILD" -j2 --target msdeform msdeform_make_large >/dev/null
"$BUILD/apps/msdeform_make_large" --huge >/dev/null
source bench/table_common.sh
threads=$(printf '%s\n' 1 2 "$(nproc)" | sort -nu)
uptime > "$OUT/load_before.txt"
for mesh in armadillo_104k.off armadillo_1664k.ply armadillo_6656k.ply; do
  stem=${mesh%.*}
  for rep in $(seq 1 "$REPEATS"); do
    for t in $threads; do
      name=${stem}_t${t}_r${rep}
      timed_msdeform "$name" --scenario=data/scenarios/armadillo_claw.json \
        --mesh="data/meshes/$mesh" --threads="$t" --frames=30 \
        --out="$OUT/$stem.ply" --report="$OUT/$name.json" --quiet
    done
  done
  rm -f "$OUT/$stem.ply"
done
uptime > "$OUT/load_after.txt"
/usr/bin/python3 bench/thread_scaling_table.py "$OUT" docs/performance_threads.md
echo "wrote docs/performance_threads.md"

#!/bin/bash
# Median frame time of msdeform on the armadillo at 26K / 104K / 416K vertices
# for the three methods (the default claw edit, 5 frames). Used by charts.py
# only when experiments/results/ has no timing table. Skips runs already done.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BIN="${MSDEFORM_BIN:-$ROOT/build/apps/msdeform}"
OUT="$ROOT/paper_figures/data/timing"
mkdir -p "$OUT"
for mesh in armadillo armadillo_104k armadillo_416k; do
  for method in multiscale static static_dense; do
    report="$OUT/${mesh}_${method}.json"
    [ -s "$report" ] && continue
    echo "timing: $mesh $method"
    # The machine is shared: keep the 1-minute load average next to each result.
    cut -d' ' -f1 /proc/loadavg > "$OUT/${mesh}_${method}.load"
    "$BIN" --scenario="$ROOT/data/scenarios/armadillo_claw.json" --mesh="$ROOT/data/meshes/$mesh.off" \
      --method="$method" --frames=5 --out="$OUT/${mesh}_${method}.off" --report="$report" --quiet
    rm -f "$OUT/${mesh}_${method}.off"
  done
done

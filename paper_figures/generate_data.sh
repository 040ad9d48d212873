#!/bin/bash
# Figure data (paper_figures/README.md) from msdeform_figure_data and msdeform,
# into paper_figures/data/. A file already there is kept unless FORCE=1.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
FIG="$ROOT/paper_figures"
D="$FIG/data"
BIN="${FIGDATA_BIN:-$ROOT/build/apps/msdeform_figure_data}"
SC="$FIG/scenarios"
mkdir -p "$D"

run() {  # run OUT ARGS...: one exporter call unless OUT exists
  local out="$1"; shift
  if [ -s "$out" ] && [ "${FORCE:-0}" != 1 ]; then return; fi
  echo "generate_data: $(basename "$out")"
  "$BIN" --out="$out" "$@"
}

# Fig. 2 and 3: lattices and multi-scale graphs.
run "$D/graphs_armadillo.json" --mode=graphs --mesh="$ROOT/data/meshes/armadillo.off" --scales=1,mid,N
run "$D/graphs_camel.json" --mode=graphs --mesh="$ROOT/data/meshes/camel.off" --scales=1
run "$D/graphs_hand.json" --mode=graphs --mesh="$ROOT/data/meshes/hand.off" --scales=1

# Fig. 4: handles, particle groups and e'.
run "$D/edit_armadillo_foot_multiscale.json" --mode=edit --scenario="$SC/armadillo_foot.json"
run "$D/edit_armadillo_foot_static_dense.json" --mode=edit --scenario="$SC/armadillo_foot.json" \
  --method=static_dense --frames=5

# Fig. 5: ours and the two ablations.
run "$D/edit_camel_leg_bend_multiscale.json" --mode=edit --scenario="$SC/camel_leg_bend.json"
run "$D/edit_camel_leg_bend_keep_left_out.json" --mode=edit --scenario="$SC/camel_leg_bend.json" \
  --keep_left_out_terms
run "$D/edit_camel_leg_bend_fix_fixed.json" --mode=edit --scenario="$SC/camel_leg_bend.json" \
  --fix_fixed_handle_nodes

# Fig. 6 / 8: large- and small-scale edits.
run "$D/edit_armadillo_claw_multiscale.json" --mode=edit \
  --scenario="$ROOT/data/scenarios/armadillo_claw.json" --frames=10
for s in armadillo_arm_raise armadillo_ear camel_neck; do
  run "$D/edit_${s}_multiscale.json" --mode=edit --scenario="$SC/$s.json"
done

# ... and two large edits of experiments/ (other models), when present.
for s in man_leg_lift dino_tail_swing; do
  if [ -f "$ROOT/experiments/scenarios/$s.json" ]; then
    run "$D/edit_${s}_multiscale.json" --mode=edit --scenario="$ROOT/experiments/scenarios/$s.json" \
      --frames=10
  fi
done
# Open issue figure: leg edits against every DG1 node free.
if [ -f "$ROOT/experiments/scenarios/man_leg_lift.json" ]; then
  run "$D/edit_man_leg_lift_static_dense.json" --mode=edit --method=static_dense --frames=5 \
    --scenario="$ROOT/experiments/scenarios/man_leg_lift.json"
fi

# Fig. 7: the thumb, ours against the 220-node static graph.
run "$D/edit_hand_thumb_multiscale.json" --mode=edit --scenario="$SC/hand_thumb.json"
run "$D/edit_hand_thumb_static.json" --mode=edit --scenario="$SC/hand_thumb.json" \
  --method=static --static_nodes=220

# The experiments' one-finger edit (middle knuckle, neighbours watched), when present.
if [ -f "$ROOT/experiments/scenarios/hand_finger.json" ]; then
  run "$D/edit_hand_finger_multiscale.json" --mode=edit \
    --scenario="$ROOT/experiments/scenarios/hand_finger.json"
  run "$D/edit_hand_finger_static.json" --mode=edit \
    --scenario="$ROOT/experiments/scenarios/hand_finger.json" --method=static --static_nodes=220
fi

# Chart: optimised nodes against P.
run "$D/nodes_vs_p_armadillo_claw.json" --mode=nodes_vs_p \
  --scenario="$ROOT/data/scenarios/armadillo_claw.json" --p_values=25,50,100,200,400,800,1600
run "$D/nodes_vs_p_armadillo_foot.json" --mode=nodes_vs_p \
  --scenario="$SC/armadillo_foot.json" --p_values=25,50,100,200,400,800,1600

# Charts from experiments' tables: when experiments/results/ has none yet, a preview from the
# runner's --quick subset (cactus and hand_finger, 5 frames) into data/experiments_quick/.
EXP_BIN="${EXPERIMENTS_BIN:-$(dirname "$(dirname "$BIN")")/experiments/msdeform_experiments}"
if [ ! -f "$ROOT/experiments/results/solvers.csv" ] && [ -x "$EXP_BIN" ] && \
   { [ ! -s "$D/experiments_quick/solvers.csv" ] || [ "${FORCE:-0}" = 1 ]; }; then
  echo "generate_data: experiments_quick (msdeform_experiments --quick)"
  "$EXP_BIN" --quick --out_dir="$D/experiments_quick"
fi

# Chart: frame time against vertex count, when neither docs/performance.md nor experiments/ has it.
if [ "${SKIP_TIMING:-0}" != 1 ] && [ ! -f "$ROOT/docs/performance.md" ] && ! ls "$ROOT"/experiments/results/*timing*.csv >/dev/null 2>&1 && \
   ! ls "$ROOT"/experiments/results/*scaling*.csv >/dev/null 2>&1; then
  bash "$FIG/measure_timing.sh"
fi

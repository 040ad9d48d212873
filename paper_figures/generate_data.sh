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

# The paper's settings together ("paper mode"; docs/decisions/README.md): its rigidity estimate, every
# fixed-handle node Half Free, Fixed nodes at the border, no Position terms on fixed vertices,
# the fixed region not pinned, one lattice particle per cell.
PAPER=(--rigidity=paper --half_free=every_fixed_handle_node --border=fixed
       --hold_fixed_vertices=false --pin_fixed_region=false --split_cells=false)
EXP="$ROOT/experiments/scenarios"

# Fig. 4: e' and group 1, the harmonic estimate (default) against the paper's, on a limb edit
# (experiments' man_foot_drag) and a small one (experiments' armadillo_ear: a band fixed).
if [ -f "$EXP/man_foot_drag.json" ] && [ -f "$EXP/armadillo_ear.json" ]; then
  run "$D/edit_man_foot_drag_multiscale.json" --mode=edit --scenario="$EXP/man_foot_drag.json" \
    --frames=10
  run "$D/edit_man_foot_drag_paper_rigidity.json" --mode=edit --scenario="$EXP/man_foot_drag.json" \
    --frames=10 --rigidity=paper
  run "$D/edit_armadillo_ear_band_multiscale.json" --mode=edit \
    --scenario="$EXP/armadillo_ear.json" --frames=10
  run "$D/edit_armadillo_ear_band_paper_rigidity.json" --mode=edit \
    --scenario="$EXP/armadillo_ear.json" --frames=10 --rigidity=paper
fi

# The leg edits figure and chart_nodes_vs_p: the armadillo foot lift, default, paper mode and
# every DG1 node free.
run "$D/edit_armadillo_foot_multiscale.json" --mode=edit --scenario="$SC/armadillo_foot.json"
run "$D/edit_armadillo_foot_paper.json" --mode=edit --scenario="$SC/armadillo_foot.json" \
  "${PAPER[@]}"
run "$D/edit_armadillo_foot_static_dense.json" --mode=edit --scenario="$SC/armadillo_foot.json" \
  --method=static_dense --frames=5

# Fig. 5: experiments' man_knee_bend (the knee bends right at a fixed band around the thigh):
# default, paper mode and the ablations, 10 frames. The Half Free ablations act on the nodes
# of an unpinned fixed region (the default pins it: no Half Free node is left).
FIG5_VARIANTS=(
  "multiscale"
  "paper ${PAPER[*]}"
  "no_pin --pin_fixed_region=false"
  "keep_left_out --pin_fixed_region=false --keep_left_out_terms"
  "fix_fixed --pin_fixed_region=false --fix_fixed_handle_nodes"
  "border_fixed --border=fixed"
  "half_free_every --pin_fixed_region=false --half_free=every_fixed_handle_node"
)
if [ -f "$EXP/man_knee_bend.json" ]; then
  for v in "${FIG5_VARIANTS[@]}"; do
    read -r tag flags <<<"$v"
    # shellcheck disable=SC2086
    run "$D/edit_man_knee_bend_$tag.json" --mode=edit --scenario="$EXP/man_knee_bend.json" \
      --frames=10 $flags
  done
fi

# Fig. 6's camel leg (the former Fig. 5 edit), default and paper mode.
run "$D/edit_camel_leg_bend_multiscale.json" --mode=edit --scenario="$SC/camel_leg_bend.json"
run "$D/edit_camel_leg_bend_paper.json" --mode=edit --scenario="$SC/camel_leg_bend.json" \
  "${PAPER[@]}"

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
# Leg edits figure: the man leg lift in paper mode and with every DG1 node free.
if [ -f "$ROOT/experiments/scenarios/man_leg_lift.json" ]; then
  run "$D/edit_man_leg_lift_paper.json" --mode=edit --frames=10 "${PAPER[@]}" \
    --scenario="$ROOT/experiments/scenarios/man_leg_lift.json"
  run "$D/edit_man_leg_lift_static_dense.json" --mode=edit --method=static_dense --frames=5 \
    --scenario="$ROOT/experiments/scenarios/man_leg_lift.json"
fi

# Fig. 7: the thumb, ours (default and paper mode) against the 220-node static graph.
run "$D/edit_hand_thumb_multiscale.json" --mode=edit --scenario="$SC/hand_thumb.json"
run "$D/edit_hand_thumb_paper.json" --mode=edit --scenario="$SC/hand_thumb.json" "${PAPER[@]}"
run "$D/edit_hand_thumb_static.json" --mode=edit --scenario="$SC/hand_thumb.json" \
  --method=static --static_nodes=220

# The experiments' one-finger edit (middle knuckle, neighbours watched), when present.
if [ -f "$ROOT/experiments/scenarios/hand_finger.json" ]; then
  run "$D/edit_hand_finger_multiscale.json" --mode=edit \
    --scenario="$ROOT/experiments/scenarios/hand_finger.json"
  run "$D/edit_hand_finger_paper.json" --mode=edit "${PAPER[@]}" \
    --scenario="$ROOT/experiments/scenarios/hand_finger.json"
  run "$D/edit_hand_finger_static.json" --mode=edit \
    --scenario="$ROOT/experiments/scenarios/hand_finger.json" --method=static --static_nodes=220
fi

# The free-limb figure: experiments' camel_hoof_lift_free_leg (body fixed, the left front hoof
# lifted, the right front leg, which touches it at the knee, free and watched), its own 30 frames
# as in table 2: default, paper mode and the 220-node static graph.
if [ -f "$EXP/camel_hoof_lift_free_leg.json" ]; then
  run "$D/edit_camel_hoof_lift_free_leg_multiscale.json" --mode=edit \
    --scenario="$EXP/camel_hoof_lift_free_leg.json"
  run "$D/edit_camel_hoof_lift_free_leg_paper.json" --mode=edit "${PAPER[@]}" \
    --scenario="$EXP/camel_hoof_lift_free_leg.json"
  run "$D/edit_camel_hoof_lift_free_leg_static.json" --mode=edit --method=static \
    --static_nodes=220 --scenario="$EXP/camel_hoof_lift_free_leg.json"
fi

# The energy figure: experiments' camel_hoof_lift_free_leg (its 30 frames, as in table 2) with
# the multi-scale method minimising Eq. 17 (--energy=ed) and the mesh's ARAP energy in the
# selected graph's subspace (--energy=arap), each named explicitly, and CGAL's ARAP (20
# iterations a frame, table 2's cgal_arap) through msdeform, which runs every registered method.
if [ -f "$EXP/camel_hoof_lift_free_leg.json" ]; then
  for e in ed arap; do
    run "$D/edit_camel_hoof_lift_free_leg_energy_$e.json" --mode=edit --energy=$e \
      --scenario="$EXP/camel_hoof_lift_free_leg.json"
  done
  CLI="${MSDEFORM_BIN:-$(dirname "$BIN")/msdeform}"
  cgal="$D/cgal_arap_camel_hoof_lift_free_leg.off"
  if [ -x "$CLI" ] && { [ ! -s "$cgal" ] || [ "${FORCE:-0}" = 1 ]; }; then
    echo "generate_data: $(basename "$cgal")"
    "$CLI" --method=cgal_arap --scenario="$EXP/camel_hoof_lift_free_leg.json" --out="$cgal" \
      --report="${cgal%.off}.report.json" --overwrite >/dev/null
  fi
fi

# Chart: optimised nodes against P.
run "$D/nodes_vs_p_armadillo_claw.json" --mode=nodes_vs_p \
  --scenario="$ROOT/data/scenarios/armadillo_claw.json" --p_values=25,50,100,200,400,800,1600
run "$D/nodes_vs_p_armadillo_foot.json" --mode=nodes_vs_p \
  --scenario="$SC/armadillo_foot.json" --p_values=25,50,100,200,400,800,1600

# Charts from experiments' tables: when experiments/results/ has none yet, a preview from the
# runner's --quick subset (cactus and hand_finger, 5 frames) and the solver lab's (the cactus, 5
# frames) into data/experiments_quick/.
EXP_BIN="${EXPERIMENTS_BIN:-$(dirname "$(dirname "$BIN")")/experiments/msdeform_experiments}"
if [ ! -f "$ROOT/experiments/results/table2.csv" ] && [ -x "$EXP_BIN" ] && \
   { [ ! -s "$D/experiments_quick/table2.csv" ] || [ "${FORCE:-0}" = 1 ]; }; then
  echo "generate_data: experiments_quick (msdeform_experiments --quick)"
  "$EXP_BIN" --quick --out_dir="$D/experiments_quick"
fi
if [ ! -f "$ROOT/experiments/results/solvers.csv" ] && [ -x "$EXP_BIN" ] && \
   { [ ! -s "$D/experiments_quick/solvers.csv" ] || [ "${FORCE:-0}" = 1 ]; }; then
  echo "generate_data: experiments_quick (msdeform_experiments --solver_lab --quick)"
  "$EXP_BIN" --solver_lab --quick --out_dir="$D/experiments_quick"
fi

# Chart: frame time against vertex count, when neither docs/performance.md nor experiments/ has it.
if [ "${SKIP_TIMING:-0}" != 1 ] && [ ! -f "$ROOT/docs/performance.md" ] && ! ls "$ROOT"/experiments/results/*timing*.csv >/dev/null 2>&1 && \
   ! ls "$ROOT"/experiments/results/*scaling*.csv >/dev/null 2>&1; then
  bash "$FIG/measure_timing.sh"
fi

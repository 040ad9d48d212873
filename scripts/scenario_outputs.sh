#!/usr/bin/env bash
# Writes the deformed mesh of every scenario under every registered method
# (the graph methods with both energies) into one folder, for checking that a
# change moves no number: run it before and after, then `diff -r` the two
# folders (the .off files hold every coordinate to round-trip precision).
#
#   bash scripts/scenario_outputs.sh build/apps/msdeform before/
#   ... change, rebuild ...
#   bash scripts/scenario_outputs.sh build/apps/msdeform after/ && diff -r before after
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
binary="${1:?usage: scenario_outputs.sh MSDEFORM_BINARY OUT_DIR}"
out="${2:?usage: scenario_outputs.sh MSDEFORM_BINARY OUT_DIR}"
[[ -x "${binary}" ]] || { echo "scenario_outputs: ERROR: ${binary}: not an executable" >&2; exit 1; }
mkdir -p "${out}"

graph_methods=(multiscale static static_dense)
other_methods=(cgal_arap cgal_sr_arap fastlsm rigid_cells full_arap)
for scenario in "${root}"/experiments/scenarios/*.json; do
  name="$(basename "${scenario}" .json)"
  runs=()
  for method in "${graph_methods[@]}"; do
    for energy in ed arap; do runs+=("${method}:${energy}"); done
  done
  for method in "${other_methods[@]}"; do runs+=("${method}:"); done
  for run in "${runs[@]}"; do
    method="${run%%:*}"
    energy="${run#*:}"
    tag="${name}_${method}${energy:+_${energy}}"
    flags=(--scenario="${scenario}" --method="${method}" --quiet --overwrite
           --out="${out}/${tag}.off" --report="${out}/${tag}.json")
    [[ -n "${energy}" ]] && flags+=(--energy="${energy}")
    "${binary}" "${flags[@]}"
    # The report's times differ run to run; keep its other fields.
    python3 - "${out}/${tag}.json" <<'PY'
import json, sys
path = sys.argv[1]
def strip(value):
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items()
                if not (k.endswith("_ms") or k in ("timings_ms", "build", "date", "wall_s"))}
    if isinstance(value, list):
        return [strip(v) for v in value]
    return value
with open(path) as f:
    report = json.load(f)
with open(path, "w") as f:
    json.dump(strip(report), f, indent=1, sort_keys=True)
PY
  done
  echo "scenario_outputs: ${name}: ${#runs[@]} runs"
done

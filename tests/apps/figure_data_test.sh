#!/usr/bin/env bash
# msdeform_figure_data's edit mode and the energy it minimised, each with a known
# answer (paper_figures/energy_figure.py labels its panels from these fields):
#   - --energy=ed and --energy=arap are recorded in the JSON ("energy", and the
#     subspace ARAP energy's "arap_clusters" / "arap_num_clusters" /
#     "arap_constraints" only with arap), and the two deformed meshes differ;
#   - --arap_clusters with --energy=ed is refused (only arap reads it);
#   - --energy=foo is refused with one line naming the flag, exit 1, no output.
#
#   bash tests/apps/figure_data_test.sh <msdeform_figure_data> <corpus>
set -uo pipefail
figure_data="$(realpath "$1")"
corpus="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
cd "${work}"
failures=0
fail() { echo "figure_data_test: $*"; failures=$((failures + 1)); }

for energy in ed arap; do
  arap_flags=()
  [[ "${energy}" == arap ]] && arap_flags=(--arap_clusters=nodes)
  "${figure_data}" --mode=edit --scenario="${corpus}/slab_x.json" --energy="${energy}" \
    "${arap_flags[@]}" --out="out/${energy}.json" 2> err.txt ||
    fail "--energy=${energy}: exit $?: $(head -c 500 err.txt)"
  grep -q "\"energy\":\"${energy}\"" "out/${energy}.json" ||
    fail "--energy=${energy}: out/${energy}.json does not record \"energy\":\"${energy}\""
done
grep -q '"arap_clusters":"nodes","arap_num_clusters":300,"arap_constraints":"exact"' out/arap.json ||
  fail "--energy=arap: the subspace ARAP options are not recorded as given"
! grep -q '"arap_clusters"' out/ed.json || fail "--energy=ed: records arap_clusters"
cmp -s out/ed.off out/arap.off && fail "--energy=ed and --energy=arap gave the same mesh"

mkdir -p bad
"${figure_data}" --mode=edit --scenario="${corpus}/slab_x.json" --energy=ed \
  --arap_clusters=nodes --out=bad/e.json 2> err.txt
code=$?
[[ "${code}" == 1 ]] || fail "--energy=ed --arap_clusters=nodes: exit ${code}, expected 1"
grep -q "arap.clusters=nodes: read only by energy=arap" err.txt ||
  fail "--energy=ed --arap_clusters=nodes: $(head -c 300 err.txt)"
[[ -e bad/e.json ]] && fail "--energy=ed --arap_clusters=nodes: wrote bad/e.json"
"${figure_data}" --mode=edit --scenario="${corpus}/slab_x.json" --energy=foo \
  --out=bad/f.json 2> err.txt
code=$?
[[ "${code}" == 1 ]] || fail "--energy=foo: exit ${code}, expected 1"
[[ "$(wc -l < err.txt)" == 1 ]] || fail "--energy=foo: stderr is not one line: $(head -c 500 err.txt)"
grep -qx "msdeform_figure_data: --energy=foo: expected ed or arap" err.txt ||
  fail "--energy=foo: stderr is '$(head -n 1 err.txt)'"
[[ -z "$(find bad -mindepth 1 | head -1)" ]] || fail "--energy=foo left $(find bad -mindepth 1)"

(( failures == 0 )) && echo "figure_data_test: ok"
(( failures == 0 ))

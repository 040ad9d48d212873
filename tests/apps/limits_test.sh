#!/usr/bin/env bash
# Limits of the executables besides msdeform's corpus, each with a known answer:
#   - --frames outside 0..100000 is refused by msdeform_figure_data and
#     msdeform_experiments with one line naming the flag (10^8 frames ran out
#     of memory with an uncaught std::bad_alloc);
#
#   bash tests/apps/limits_test.sh <msdeform> <msdeform_figure_data> <run_experiments> <corpus>
set -uo pipefail
msdeform="$(realpath "$1")"
figure_data="$(realpath "$2")"
experiments="$(realpath "$3")"
corpus="$(cd "$4" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
cd "${work}"
failures=0
fail() { echo "limits_test: $*"; failures=$((failures + 1)); }

# expect_one_line <name> <expected text>: err.txt is exactly that one line.
expect_one_line() {
  local first
  first="$(head -n 1 err.txt)"
  [[ "$(wc -l < err.txt)" == 1 ]] || fail "$1: stderr is not one line: $(head -c 500 err.txt)"
  [[ "${first}" == *"$2"* ]] || fail "$1: stderr lacks '$2': ${first}"
}

for frames in -1 100001 100000000; do
  mkdir -p out
  "${figure_data}" --mode=edit --scenario="${corpus}/slab_x.json" --frames="${frames}" \
    --out=out/f.json 2> err.txt
  code=$?
  [[ "${code}" == 1 ]] || fail "figure_data --frames=${frames}: exit ${code}, expected 1"
  expect_one_line "figure_data --frames=${frames}" \
    "msdeform_figure_data: --frames=${frames}: expected 0..100000"
  "${experiments}" --quick --frames="${frames}" --out_dir=out/exp 2> err.txt
  code=$?
  [[ "${code}" == 1 ]] || fail "experiments --frames=${frames}: exit ${code}, expected 1"
  expect_one_line "experiments --frames=${frames}" \
    "msdeform_experiments: --frames=${frames}: expected 0..100000"
  [[ -z "$(find out -mindepth 1 | head -1)" ]] || fail "--frames=${frames} left $(find out)"
done

(( failures == 0 )) && echo "limits_test: ok"
(( failures == 0 ))

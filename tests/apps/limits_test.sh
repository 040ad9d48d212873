#!/usr/bin/env bash
# Limits of the executables besides msdeform's corpus, each with a known answer:
#   - --frames outside 0..100000 is refused by msdeform_figure_data and
#     msdeform_experiments with one line naming the flag (10^8 frames ran out
#     of memory with an uncaught std::bad_alloc);
#   - running out of memory (a lattice grid of 2 * 10^8 cells under a 500 MB
#     address-space limit) ends msdeform and msdeform_figure_data with one
#     line "<program>: out of memory: ...", exit 1 and no output left behind.
#
# The out-of-memory part needs an address-space limit, which AddressSanitizer's
# shadow memory cannot run under: a sanitized build (5th argument "sanitized")
# runs the rest, the plain build all of it.
#
#   bash tests/apps/limits_test.sh <msdeform> <msdeform_figure_data> <run_experiments> <corpus> \
#       [plain|sanitized]
set -uo pipefail
msdeform="$(realpath "$1")"
figure_data="$(realpath "$2")"
experiments="$(realpath "$3")"
corpus="$(cd "$4" && pwd)"
build_kind="${5:-plain}"
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

if [[ "${build_kind}" == sanitized ]]; then
  echo "limits_test: sanitized build: the out-of-memory runs are left to the plain build"
  (( failures == 0 )) && echo "limits_test: ok"
  exit $(( failures == 0 ? 0 : 1 ))
fi

# bar.off is 4 x 1 x 1: cell width 0.0027 gives a grid of about 2.1 * 10^8
# cells (under max_grid_cells = 2^28), 820 MB of cell ids.
mkdir -p out
(ulimit -v 500000; "${msdeform}" --quiet --scenario="${corpus}/slab_x.json" --cell_width=0.0027 \
  --out=out/m.off) 2> err.txt
code=$?
[[ "${code}" == 1 ]] || fail "msdeform out of memory: exit ${code}, expected 1"
expect_one_line "msdeform out of memory" "msdeform: out of memory: std::bad_alloc"
(ulimit -v 500000; "${figure_data}" --mode=edit --scenario="${corpus}/slab_x.json" \
  --cell_width=0.0027 --out=out/f.json) 2> err.txt
code=$?
[[ "${code}" == 1 ]] || fail "figure_data out of memory: exit ${code}, expected 1"
expect_one_line "figure_data out of memory" "msdeform_figure_data: out of memory: std::bad_alloc"
[[ -z "$(find out -mindepth 1 | head -1)" ]] || fail "out of memory left $(find out -mindepth 1)"

(( failures == 0 )) && echo "limits_test: ok"
(( failures == 0 ))

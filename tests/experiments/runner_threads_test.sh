#!/usr/bin/env bash
# msdeform_experiments measures on one thread unless told otherwise: with no
# thread flag the tables' settings say 1 thread (both spellings of the
# option, --threads and --num_threads, default to it), and --threads=2 is
# recorded as 2.
#
#   bash tests/experiments/runner_threads_test.sh <msdeform_experiments binary> <repository root>
set -euo pipefail
runner="$(realpath "$1")"
cd "$2"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
for flag in "" "--threads=2"; do
  out="${work}/out${flag//[-=]/_}"
  "${runner}" --quick --only=cactus --methods=static --frames=1 --out_dir="${out}" ${flag} > /dev/null
  expected="1 thread(s)"
  [[ -n "${flag}" ]] && expected="2 thread(s)"
  grep -q "${expected}" "${out}/table2.csv" ||
    { echo "runner_threads_test: ${flag:-no flag}: table2.csv does not say ${expected}"; exit 1; }
done
echo "runner_threads_test: one thread by default, --threads recorded"

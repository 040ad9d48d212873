#!/usr/bin/env bash
# Same seed, same bytes, whatever the thread count: runs msdeform three times
# with the same inputs and seed, on 1, 2 and 3 threads, and compares the
# deformed meshes and node dumps byte for byte. The reports differ only in their
# timings (timings_ms), date, command line, thread count and output path, which
# are left out.
#
#   bash tests/apps/determinism_test.sh <msdeform binary> <corpus folder>
set -euo pipefail
msdeform="$(realpath "$1")"
corpus="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
for method in multiscale static; do
  for run in 1 2 3; do
    "${msdeform}" --quiet --scenario="${corpus}/slab_x.json" --method="${method}" --seed=7 \
      --threads="${run}" --overwrite --out="${work}/${run}.off" --report="${work}/${run}.json" \
      --dump_nodes="${work}/${run}.csv"
    sed -e '/"timings_ms"/,/^  }/d' -e '/"command_line"/,/]/d' -e '/"output"/d' -e '/"date"/d' \
      -e '/"threads"/d' -e '/num_threads"/d' \
      "${work}/${run}.json" > "${work}/${run}.json.stable"
  done
  for file in off csv json.stable; do
    for run in 2 3; do
      if ! cmp "${work}/1.${file}" "${work}/${run}.${file}"; then
        echo "determinism_test: ${method}: .${file} on 1 and ${run} threads differ"
        exit 1
      fi
    done
  done
done
echo "determinism_test: identical outputs"

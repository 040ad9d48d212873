#!/usr/bin/env bash
# Same bytes on any thread count, on a mesh large enough that every stage
# takes its parallel path: a cylinder of 116,162 vertices
# (tests/apps/thread_determinism_mesh.cc) bent sideways, read as OFF text (the
# parallel parse) and as binary PLY, each run on 1, 2 and 3 threads. Compares
# the deformed meshes, the node dumps and the reports (less their timings,
# date, command line, thread count and output path) byte for byte.
# (tests/apps/determinism_test.sh does the same on a small corpus scene, for
# both methods.)
#
#   bash tests/apps/thread_determinism_test.sh <msdeform binary> <thread_determinism_mesh binary>
set -euo pipefail
msdeform="$(realpath "$1")"
make_mesh="$(realpath "$2")"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
"${make_mesh}" "${work}/cylinder.off" "${work}/cylinder.ply" > /dev/null
for format in off ply; do
  # The bottom tenth fixed, the top tenth dragged sideways by a tenth of the
  # bounding-box diagonal over three frames.
  cat > "${work}/bend_${format}.json" <<EOF
{
  "mesh": "cylinder.${format}",
  "fixed": [{"slab": {"axis": "z", "from": 0, "to": 0.1}}],
  "handle": {"slab": {"axis": "z", "from": 0.9, "to": 1}},
  "transform": {"translation_rel": [0.1, 0, 0]},
  "frames": 3
}
EOF
  for run in 1 2 3; do
    out="${work}/${format}_${run}"
    "${msdeform}" --quiet --scenario="${work}/bend_${format}.json" --threads="${run}" --overwrite \
      --out="${out}.${format}" --report="${out}.json" --dump_nodes="${out}.csv"
    sed -e '/"timings_ms"/,/^  }/d' -e '/"command_line"/,/]/d' -e '/"output"/d' -e '/"date"/d' \
      -e '/"threads"/d' -e '/num_threads"/d' "${out}.json" > "${out}.json.stable"
  done
  for file in "${format}" csv json.stable; do
    for run in 2 3; do
      if ! cmp "${work}/${format}_1.${file}" "${work}/${format}_${run}.${file}"; then
        echo "thread_determinism_test: ${format} input: .${file} on 1 and ${run} threads differ"
        exit 1
      fi
    done
  done
done
echo "thread_determinism_test: identical outputs on 1, 2 and 3 threads (OFF and PLY input)"

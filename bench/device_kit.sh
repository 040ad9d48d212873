#!/usr/bin/env bash
# Packs the Release build into BUILD_DIR/device-kit, a folder that runs the
# thread-scaling runs of bench/thread_scaling_table.sh on another Linux x86-64
# machine, one without Debian's packages: msdeform, msdeform_make_large, every
# shared library they load (as ldd lists them here) and this machine's dynamic
# loader in lib/, the 26K armadillo and the claw drag scenario, and run.sh.
#
#   bench/device_kit.sh [BUILD_DIR]          (default: build)
#
# On the other machine, from anywhere:
#   OUT=/tmp/kit-out bash device-kit/run.sh [THREADS...]      (default: 1 2 4 8 16)
# makes the 104K, 1.66M and 6.66M armadillos in device-kit/meshes/ (once, about
# a minute), runs the claw drag (30 frames, the default solver) on each at each
# thread count, and leaves $OUT/<mesh stem>_t<threads>.json (msdeform's
# reports) and $OUT/machine.txt; bench/thread_scaling_table.py $OUT OUT.md
# formats them here.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
if [[ "$(grep -s '^CMAKE_BUILD_TYPE:' "$BUILD/CMakeCache.txt" | cut -d= -f2)" != Release ]]; then
  echo "device_kit.sh: $BUILD is not a Release build (cmake -DCMAKE_BUILD_TYPE=Release)" >&2
  exit 1
fi
test -f data/meshes/armadillo.off ||
  { echo "device_kit.sh: missing data/meshes/armadillo.off (data/fetch_meshes.sh)" >&2; exit 1; }
cmake --build "$BUILD" -j2 --target msdeform msdeform_make_large >/dev/null
kit="$BUILD/device-kit"
rm -rf "$kit"
mkdir -p "$kit/lib" "$kit/meshes" "$kit/scenarios"
cp "$BUILD/apps/msdeform" "$BUILD/apps/msdeform_make_large" "$kit/"
# Each library under the name the programs ask for (its soname), its contents
# copied through any symbolic links; the loader under its own name.
ldd "$kit/msdeform" "$kit/msdeform_make_large" | awk '$2 == "=>" && $3 ~ /^\// {print $3}' |
  sort -u | while read -r library; do cp -L "$library" "$kit/lib/"; done
cp -L /lib64/ld-linux-x86-64.so.2 "$kit/lib/"
cp data/meshes/armadillo.off "$kit/meshes/"
cp data/scenarios/armadillo_claw.json "$kit/scenarios/"  # its mesh: ../meshes/armadillo.off

cat > "$kit/run.sh" <<'EOF'
#!/usr/bin/env bash
# The claw drag on the 104K, 1.66M and 6.66M armadillo at each thread count
# given (default 1 2 4 8 16), with the libraries and loader of lib/ only.
# Reports: $OUT/<mesh stem>_t<threads>.json (OUT default /tmp/kit-out), and
# $OUT/machine.txt (cores, CPU), $OUT/load_before.txt, $OUT/load_after.txt.
set -euo pipefail
OUT=$(realpath -m "${OUT:-/tmp/kit-out}")
cd "$(dirname "$0")"
threads=("$@")
[[ ${#threads[@]} -gt 0 ]] || threads=(1 2 4 8 16)
run() { ./lib/ld-linux-x86-64.so.2 --library-path ./lib "$@"; }
load() { uptime 2>/dev/null || cat /proc/loadavg; }
mkdir -p "$OUT"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cpu() { grep -m1 "^$1[[:space:]]*:" /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'; }
flags=" $(cpu flags) "
simd=$([[ $flags == *" avx512f "* ]] && echo AVX-512 || { [[ $flags == *" avx2 "* ]] && echo AVX2 || echo "no AVX2"; })
printf 'cores: %s\ncpu: %s\ncpu family: %s\nmodel: %s\nsimd: %s\n' \
  "$(nproc)" "$(cpu 'model name')" "$(cpu 'cpu family')" "$(cpu model)" "$simd" > "$OUT/machine.txt"
run ./msdeform_make_large --mesh_dir=meshes --huge >/dev/null
load > "$OUT/load_before.txt"
# ms NAME REPORT: the first number written as "NAME": in the report.
ms() { grep -m1 -o "\"$1\": [0-9][0-9.e+-]*" "$2" | cut -d' ' -f2; }
for mesh in armadillo_104k.off armadillo_1664k.ply armadillo_6656k.ply; do
  stem=${mesh%.*}
  for t in "${threads[@]}"; do
    report="$OUT/${stem}_t$t.json"
    if ! run ./msdeform --scenario=scenarios/armadillo_claw.json --mesh="meshes/$mesh" \
        --threads="$t" --frames=30 --out="$scratch/$stem.ply" --report="$report" \
        --overwrite --quiet; then
      echo "run.sh: msdeform failed on $mesh at $t threads" >&2
      exit 1
    fi
    awk -v name="$stem" -v t="$t" -v load="$(ms load "$report")" \
        -v pre="$(ms precompute "$report")" -v rig="$(ms rigidity "$report")" \
        -v setup="$(ms setup "$report")" -v frame="$(ms frame_median "$report")" \
        -v solve="$(ms solve_median "$report")" -v skin="$(ms skin_median "$report")" \
        'BEGIN { printf "%s --threads=%d: load %.0f, precompute %.0f, layout %.0f, first frame after %.0f ms; frame %.2f ms (solve %.2f, skin %.2f)\n",
                 name, t, load, pre, rig + setup, load + pre + rig + setup, frame, solve, skin }'
  done
done
load > "$OUT/load_after.txt"
EOF
chmod +x "$kit/run.sh"
echo "device_kit.sh: wrote $kit ($(du -sh "$kit" | cut -f1)); run: bash $kit/run.sh [THREADS...]"

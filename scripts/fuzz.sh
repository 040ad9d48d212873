#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz/ with clang (plus AddressSanitizer
# and UndefinedBehaviorSanitizer) in build-fuzz/ and runs each for a bounded
# time, starting from the saved inputs in tests/data/fuzz/<target>/. Not part
# of CI. A crash stops the run and leaves crash-<hash> in build-fuzz/findings/;
# fix it, then copy the input to tests/data/fuzz/<target>/ so the normal suite
# (fuzz/fuzz_regression_test) replays it from then on.
#
#   bash scripts/fuzz.sh [seconds per target, default 60] [targets...]
#   e.g. bash scripts/fuzz.sh 300 off obj
#
# Needs clang and libclang-rt-14-dev (Debian bookworm); installs them when root.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
(( ${#targets[@]} )) || targets=(sel def scenario off obj ply stl)
step() { echo "fuzz: $*"; }

for package in clang libclang-rt-14-dev; do
  if ! dpkg-query -W -f='${db:Status-Abbrev}' "${package}" 2>/dev/null | grep -q '^ii'; then
    [[ ${EUID} -eq 0 ]] || { echo "fuzz: ${package} is missing; rerun as root" >&2; exit 1; }
    step "installing ${package}"
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${package}"
  fi
done
bash "${root}/scripts/install_deps.sh"

build="${root}/build-fuzz"
mkdir -p "${build}"
step "configuring ${build} (clang, -fsanitize=fuzzer-no-link,address,undefined)"
cmake -S "${root}" -B "${build}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DMSDEFORM_FUZZ=ON \
  "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined" \
  "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined" > "${build}/configure.log" 2>&1 ||
  { cat "${build}/configure.log"; exit 1; }
step "compiling ${targets[*]}"
cmake --build "${build}" -j2 --target "${targets[@]/%/_fuzzer}"

mkdir -p "${build}/findings"
status=0
for target in "${targets[@]}"; do
  corpus="${build}/corpus/${target}"
  mkdir -p "${corpus}"
  step "${target}: ${seconds} s"
  # The working corpus grows in build-fuzz/corpus/<target>; the saved inputs
  # are read-only seeds. -max_len keeps inputs small and runs fast.
  if ! (cd "${build}/findings" && "${build}/tests/fuzz/${target}_fuzzer" \
          -max_total_time="${seconds}" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
          -print_final_stats=1 "${corpus}" "${root}/tests/data/fuzz/${target}" \
          > "${build}/findings/${target}.log" 2>&1); then
    step "${target}: FOUND A CRASH, see ${build}/findings/${target}.log"
    status=1
  fi
  grep -E '^stat::number_of_executed_units|^stat::new_units_added' "${build}/findings/${target}.log" |
    sed "s/^/fuzz: ${target}: /" || true
done
exit "${status}"

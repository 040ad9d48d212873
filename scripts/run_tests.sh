#!/usr/bin/env bash
# Builds everything (scripts/build.sh) and runs the whole test suite with
# ctest: the C++ tests, the command line, the Python module (pytest) and
# msdeform as another project's dependency (installed, and added as a
# subdirectory). Then builds the libraries' own tests again with
# AddressSanitizer and UndefinedBehaviorSanitizer in build-asan/ (-O1,
# assertions on; target msdeform_library_tests, the ctest label "library":
# core, energies, solvers, scales, methods, the flags, the fuzz corpus replay,
# examples, docs) and runs them there. The programs' end-to-end tests run in the plain
# pass only (docs/decisions/robustness.md says why).
# Exits non-zero if a build or any test fails. MSDEFORM_SKIP_ASAN=1 skips the
# second part (for a quick local run; CI never sets it).
#
#   bash scripts/run_tests.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Each phase ends with its wall time, to see where a CI run spends it.
phase() { echo "run_tests: [${SECONDS} s] $*"; }
bash "${root}/scripts/build.sh"
phase "built"

echo "run_tests: ctest --test-dir build --output-on-failure -j2"
ctest --test-dir "${root}/build" --output-on-failure -j2
phase "plain tests passed"

if [[ "${MSDEFORM_SKIP_ASAN:-0}" == 1 ]]; then
  echo "run_tests: MSDEFORM_SKIP_ASAN=1: skipping the sanitizer build"
  exit 0
fi
asan="${root}/build-asan"
echo "run_tests: configuring ${asan} (-DMSDEFORM_SANITIZE=ON, -O1)"
cmake -S "${root}" -B "${asan}" -DMSDEFORM_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
  -DMSDEFORM_BUILD_PYTHON=OFF -DMSDEFORM_BUILD_BENCHMARKS=OFF -DMSDEFORM_INSTALL=OFF
echo "run_tests: compiling the libraries' tests with sanitizers (-j2)"
cmake --build "${asan}" -j2 --target msdeform_library_tests
phase "sanitizer build done"
# ASan's defaults (leaks reported too); UBSan findings stop the test
# (-fno-sanitize-recover) with a stack trace.
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
echo "run_tests: ctest --test-dir build-asan --output-on-failure -j2 (sanitizers)"
ctest --test-dir "${asan}" --output-on-failure -j2 --timeout 1200 --no-tests=error --label-regex '^library$'
phase "sanitizer tests passed"

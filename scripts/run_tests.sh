#!/usr/bin/env bash
# Builds everything (scripts/build.sh) and runs the whole test suite with
# ctest. Exits non-zero if the build or any test fails.
#
#   bash scripts/run_tests.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${root}/scripts/build.sh"

echo "run_tests: ctest --test-dir build --output-on-failure -j2"
ctest --test-dir "${root}/build" --output-on-failure -j2

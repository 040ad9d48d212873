#!/usr/bin/env bash
# Builds everything (scripts/build.sh) and runs the main executable from the
# repository root. Arguments go to msdeform; with none it runs its embedded
# default (the armadillo).
#
#   bash scripts/run_main.sh [msdeform flags...]
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "${root}/scripts/build.sh"

binary="${root}/build/apps/msdeform"
if [[ ! -x "${binary}" ]]; then
  echo "run_main: ERROR: ${binary} was not built" >&2
  exit 1
fi
cd "${root}"
echo "run_main: build/apps/msdeform $*"
exec "${binary}" "$@"

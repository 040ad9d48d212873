#!/usr/bin/env bash
# Installs what is missing, builds msdeform in build/ (Release) and brings the
# real meshes into data/meshes/. Safe to rerun: each step skips done work.
#
#   bash scripts/build.sh
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
step() { echo "build: $*"; }

step "dependencies"
bash "${root}/scripts/install_deps.sh"

step "configuring ${root}/build (Release)"
cmake -S "${root}" -B "${root}/build" -DCMAKE_BUILD_TYPE=Release

step "compiling (-j2)"
cmake --build "${root}/build" -j2

step "real meshes"
bash "${root}/data/fetch_meshes.sh"

step "generated meshes (large armadillo variants, cylinder)"
"${root}/build/apps/msdeform_make_large"

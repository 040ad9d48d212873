#!/usr/bin/env bash
# Installs the Debian bookworm packages msdeform needs to build and test, and
# only those that are missing. Run as root on a fresh machine; a rerun with
# everything present does nothing and needs no root.
#
#   bash scripts/install_deps.sh
set -euo pipefail

packages=(
  cmake g++ make                   # toolchain (OpenMP comes with g++)
  libeigen3-dev                    # dense and sparse linear algebra
  libceres-dev                     # solver (Ceres::ceres, 2.1)
  libsuitesparse-dev               # CHOLMOD for the Gauss-Newton backend (optional linear solver)
  libgoogle-glog-dev libgflags-dev # logging, command-line flags
  libopenmesh-dev                  # mesh I/O and Loop subdivision
  nlohmann-json3-dev               # scenario and report JSON
  libgtest-dev libbenchmark-dev    # tests and benchmarks
  libcgal-dev                      # CGAL headers
  pybind11-dev python3-dev         # the Python module
  python3-numpy python3-pytest     # its arrays and its tests
  python3-dask python3-distributed # sweeps over many runs (python/msdeform/sweep)
  openssl                          # the sweep tests' TLS certificates (not in a minimal image)
  python3-matplotlib               # the charts of paper_figures/ and of sweeps
  libglfw3-dev libimgui-dev        # the editor's window and interface (apps/msdeform_editor)
  libstb-dev                       # its PNG screenshots
  xvfb xauth libgl1-mesa-dri       # the editor headless (tests, figures): X server, Mesa's renderer
)

step() { echo "install_deps: $*"; }
die() { echo "install_deps: ERROR: $*" >&2; exit 1; }

missing=()
for package in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${db:Status-Abbrev}' "${package}" 2>/dev/null || true)"
  [[ "${status}" == ii* ]] || missing+=("${package}")
done

if (( ${#missing[@]} == 0 )); then
  step "all ${#packages[@]} packages installed; nothing to do"
  exit 0
fi

step "missing: ${missing[*]}"
[[ ${EUID} -eq 0 ]] || die "installing packages needs root; rerun as root (or sudo)"
export DEBIAN_FRONTEND=noninteractive
install() { apt-get install -y --no-install-recommends "${missing[@]}"; }
if ! install; then
  step "apt-get install failed; running apt-get update and retrying"
  apt-get update || die "apt-get update failed; check the network and /etc/apt/sources.list"
  install || die "apt-get install ${missing[*]} failed"
fi
step "installed ${#missing[@]} packages"

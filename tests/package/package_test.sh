#!/usr/bin/env bash
# msdeform as another project's dependency: builds tests/package/downstream,
# a project outside msdeform's tree, against
#   install       msdeform installed with `cmake --install BUILD --prefix TMP`
#                 and found with find_package(msdeform CONFIG REQUIRED);
#   subdirectory  msdeform's source tree added with add_subdirectory (tests,
#                 apps, experiments are OFF there; only drag_path is built,
#                 with the one library it links, msdeform::core);
# then runs its programs. Everything happens in a temporary folder, removed at exit.
#
#   bash tests/package/package_test.sh install BUILD_DIR
#   bash tests/package/package_test.sh subdirectory
set -euo pipefail

mode="${1:?usage: package_test.sh install BUILD_DIR | subdirectory}"
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
cp -r "${source_dir}/tests/package/downstream" "${work}/downstream"

case "${mode}" in
  install)
    build_dir="${2:?usage: package_test.sh install BUILD_DIR}"
    cmake --install "${build_dir}" --prefix "${work}/prefix" > "${work}/install.log"
    [[ -f "${work}/prefix/include/msdeform/scales/handle_setup.h" ]] \
      || { echo "package_test: handle_setup.h not installed under include/msdeform/scales" >&2; exit 1; }
    configure=(-DCMAKE_PREFIX_PATH="${work}/prefix")
    # The Python module, when the build has it, imports from where it was
    # installed with nothing but PYTHONPATH (README.md, "Python").
    if grep -q "^MSDEFORM_BUILD_PYTHON:BOOL=ON" "${build_dir}/CMakeCache.txt"; then
      python_dir="$(grep "^MSDEFORM_PYTHON_INSTALL_DIR:" "${build_dir}/CMakeCache.txt" | cut -d= -f2)"
      python="$(grep "^Python3_EXECUTABLE:" "${build_dir}/CMakeCache.txt" | cut -d= -f2)"
      (cd "${work}" && PYTHONPATH="${work}/prefix/${python_dir}" "${python}" -c '
import numpy as np, msdeform
V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
d = msdeform.Method(V, F)
d.set_handles(np.full(4, 2))
M = np.eye(4); M[:3, 3] = [1, 2, 3]
assert np.abs(d.drag(M) - (V + [1, 2, 3])).max() < 1e-9
assert msdeform.__file__.startswith("'"${work}"'/prefix/"), msdeform.__file__
') || { echo "package_test: the installed Python module does not import and drag" >&2; exit 1; }
    fi
    ;;
  subdirectory)
    configure=(-DMSDEFORM_SOURCE_DIR="${source_dir}")
    ;;
  *)
    echo "package_test: unknown mode '${mode}' (install or subdirectory)" >&2
    exit 2
    ;;
esac

cmake -S "${work}/downstream" -B "${work}/build" -DCMAKE_BUILD_TYPE=Release \
  "${configure[@]}" > "${work}/configure.log" \
  || { cat "${work}/configure.log"; exit 1; }
if [[ "${mode}" == subdirectory ]]; then
  # A subproject builds the libraries only.
  for option in APPS EXPERIMENTS BENCHMARKS PYTHON TESTS INSTALL; do
    grep -q "^MSDEFORM_BUILD_${option}:BOOL=OFF\|^MSDEFORM_${option}:BOOL=OFF" \
      "${work}/build/CMakeCache.txt" \
      || { echo "package_test: MSDEFORM_*${option} is not OFF in a subproject" >&2; exit 1; }
  done
fi
if [[ "${mode}" == subdirectory ]]; then
  programs=(drag_path)
else
  programs=(drag_path bend_bar list_methods)
fi
for program in "${programs[@]}"; do
  cmake --build "${work}/build" -j2 --target "${program}" >> "${work}/build.log" \
    || { cat "${work}/build.log"; exit 1; }
done
for program in "${programs[@]}"; do "${work}/build/${program}"; done

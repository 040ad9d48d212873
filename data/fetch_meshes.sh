#!/usr/bin/env bash
# Brings the real meshes msdeform works on into data/meshes/ from Debian's
# libcgal-demo package, and checks each one against data/meshes.sha256.
#
#   bash data/fetch_meshes.sh
#
# The .deb is kept in data/cache/ so a rerun needs no network. When every file
# listed in data/meshes.sha256 is already present and matches, nothing is done.
# Any failure (download, extraction, checksum) stops the script with a message.
set -euo pipefail

data_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
cache_dir="${data_dir}/cache"
mesh_dir="${data_dir}/meshes"
sums="${data_dir}/meshes.sha256"
package="libcgal-demo"
# Inside the package, and inside its two archives.
doc_dir="usr/share/doc/libcgal-dev"
off_dir="data/meshes"                                # in data.tar.gz
sel_dir="examples/Surface_mesh_deformation/data"    # in examples.tar.gz

step() { echo "fetch_meshes: $*"; }
die() { echo "fetch_meshes: ERROR: $*" >&2; exit 1; }

[[ -s "${sums}" ]] || die "missing checksum list ${sums}"
mapfile -t names < <(awk 'NF == 2 { print $2 }' "${sums}")
(( ${#names[@]} > 0 )) || die "no entries in ${sums}"

# True when every listed file is in data/meshes/ and matches its checksum.
all_present_and_verified() {
  local name
  for name in "${names[@]}"; do
    [[ -f "${mesh_dir}/${name}" ]] || return 1
  done
  (cd "${mesh_dir}" && sha256sum --check --status --strict "${sums}")
}

if all_present_and_verified; then
  step "all ${#names[@]} files present and verified in ${mesh_dir}; nothing to do"
  exit 0
fi

mkdir -p "${cache_dir}" "${mesh_dir}"

# 1. The package, from the cache or from the archive.
deb="$(find "${cache_dir}" -maxdepth 1 -name "${package}_*.deb" | sort -V | tail -n 1)"
if [[ -n "${deb}" ]]; then
  step "using cached package ${deb}"
else
  download_dir="$(mktemp -d "${cache_dir}/download.XXXXXX")"
  trap 'rm -rf "${download_dir}"' EXIT
  # apt downloads as its _apt user when that user can write the folder.
  if [[ ${EUID} -eq 0 ]] && id _apt >/dev/null 2>&1; then
    chown _apt "${download_dir}"
  fi
  step "downloading ${package} with apt-get download into ${cache_dir}"
  if ! (cd "${download_dir}" && apt-get download "${package}"); then
    step "download failed; running apt-get update and retrying"
    apt-get update || die "apt-get update failed (run as root, check the network)"
    (cd "${download_dir}" && apt-get download "${package}") ||
      die "apt-get download ${package} failed"
  fi
  deb="$(find "${download_dir}" -maxdepth 1 -name "${package}_*.deb" | head -n 1)"
  [[ -n "${deb}" ]] || die "apt-get download left no ${package}_*.deb"
  mv "${deb}" "${cache_dir}/"
  deb="${cache_dir}/$(basename "${deb}")"
  rm -rf "${download_dir}"
  trap - EXIT
fi

# 2. Unpack only what is needed into a scratch folder.
work_dir="$(mktemp -d "${cache_dir}/extract.XXXXXX")"
trap 'rm -rf "${work_dir}"' EXIT
step "unpacking ${deb}"
dpkg-deb -x "${deb}" "${work_dir}/pkg" ||
  die "dpkg-deb could not unpack ${deb}; delete it and rerun to download it again"
for archive in data.tar.gz examples.tar.gz; do
  [[ -f "${work_dir}/pkg/${doc_dir}/${archive}" ]] ||
    die "${deb} has no ${doc_dir}/${archive}"
done

off_members=()
sel_members=()
for name in "${names[@]}"; do
  case "${name}" in
    *.off) off_members+=("${off_dir}/${name}") ;;
    *) sel_members+=("${sel_dir}/${name}") ;;
  esac
done
step "extracting ${#off_members[@]} meshes from data.tar.gz"
tar -xzf "${work_dir}/pkg/${doc_dir}/data.tar.gz" -C "${work_dir}" "${off_members[@]}"
if (( ${#sel_members[@]} > 0 )); then
  step "extracting ${#sel_members[@]} handle files from examples.tar.gz"
  tar -xzf "${work_dir}/pkg/${doc_dir}/examples.tar.gz" -C "${work_dir}" "${sel_members[@]}"
fi

# 3. Check before anything lands in data/meshes/.
mkdir -p "${work_dir}/out"
for member in "${off_members[@]}" "${sel_members[@]}"; do
  mv "${work_dir}/${member}" "${work_dir}/out/"
done
step "verifying extracted files against ${sums}"
(cd "${work_dir}/out" && sha256sum --check --quiet --strict "${sums}") ||
  die "checksum mismatch in ${deb}: the package differs from the one data/meshes.sha256 was made from"

# 4. Copy in, each file through a temporary name so none is left half written.
step "copying ${#names[@]} files into ${mesh_dir}"
for name in "${names[@]}"; do
  cp "${work_dir}/out/${name}" "${mesh_dir}/.${name}.tmp"
  mv -f "${mesh_dir}/.${name}.tmp" "${mesh_dir}/${name}"
done

all_present_and_verified || die "files in ${mesh_dir} do not match ${sums} after copying"
step "done: ${#names[@]} files verified in ${mesh_dir}"

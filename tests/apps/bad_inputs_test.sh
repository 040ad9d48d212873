#!/usr/bin/env bash
# Runs msdeform on every entry of the bad-input corpus (MANIFEST.tsv in the
# corpus folder) and checks, for each:
#   - the exit code is the expected one, and no signal ended the run;
#   - on failure: stderr is exactly one line, "msdeform: ...", containing the
#     expected text (which names the file, field or line), and no output file
#     is left (the temporary output folder stays empty);
#   - on success: the mesh and the report were written;
#   - in every case: no file of the corpus changed and none was added.
#
#   bash tests/apps/bad_inputs_test.sh <msdeform binary> <corpus folder> [name filter]
set -uo pipefail

msdeform="$(realpath "$1")"
corpus="$(cd "$2" && pwd)"
filter="${3:-}"
manifest="${corpus}/MANIFEST.tsv"
[[ -x "${msdeform}" ]] || { echo "bad_inputs_test: ${msdeform} is not executable" >&2; exit 2; }
[[ -f "${manifest}" ]] || { echo "bad_inputs_test: no ${manifest}" >&2; exit 2; }

work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
snapshot() { (cd "${corpus}" && find . -type f -print0 | sort -z | xargs -0 sha256sum); }
snapshot > "${work}/before"

failures=0 count=0
fail() { echo "FAIL ${name}: $*"; failures=$((failures + 1)); }

while IFS=$'\t' read -r name expected message args; do
  [[ -z "${name}" || "${name}" == \#* ]] && continue
  [[ -n "${filter}" && "${name}" != *${filter}* ]] && continue
  count=$((count + 1))
  out="${work}/out"
  rm -rf "${out}" && mkdir "${out}"
  args="${args//@BAD@/${corpus}}"
  args="${args//@OUT@/${out}}"
  message="${message//@BAD@/${corpus}}"
  message="${message//@OUT@/${out}}"
  read -r -a argv <<< "${args}"
  [[ " ${args}" == *" --out="* ]] || argv+=("--out=${out}/out.off")
  [[ " ${args}" == *" --report="* ]] || argv+=("--report=${out}/out.json")
  (cd "${work}" && timeout 120 "${msdeform}" --quiet "${argv[@]}" > "${work}/stdout" 2> "${work}/stderr")
  code=$?
  if (( code > 128 )); then
    fail "ended by signal $((code - 128)) (exit ${code}); stderr: $(head -c 2000 "${work}/stderr")"
    continue
  fi
  if [[ "${code}" != "${expected}" ]]; then
    fail "exit ${code}, expected ${expected}; stderr: $(head -c 2000 "${work}/stderr")"
    continue
  fi
  if [[ "${expected}" == 0 ]]; then
    [[ -s "${out}/out.off" && -s "${out}/out.json" ]] || fail "exit 0 but no output written"
    continue
  fi
  lines="$(wc -l < "${work}/stderr")"
  first="$(head -n 1 "${work}/stderr")"
  if [[ "${lines}" != 1 || "$(wc -c < "${work}/stderr")" != "$(( ${#first} + 1 ))" ]]; then
    fail "stderr is not exactly one line:"; cat "${work}/stderr"
  elif [[ "${first}" != "msdeform: "* ]]; then
    fail "stderr does not start with 'msdeform: ': ${first}"
  elif [[ "${first}" != *"${message}"* ]]; then
    fail "stderr lacks '${message}': ${first}"
  fi
  leftover="$(find "${out}" -mindepth 1 | head -5)"
  [[ -z "${leftover}" ]] || fail "left files behind after failing: ${leftover}"
done < "${manifest}"

snapshot > "${work}/after"
if ! diff -q "${work}/before" "${work}/after" > /dev/null; then
  echo "FAIL: the corpus changed during the runs:"
  diff "${work}/before" "${work}/after"
  failures=$((failures + 1))
fi
(( count > 0 )) || { echo "bad_inputs_test: no entry matched '${filter}'"; exit 1; }
echo "bad_inputs_test: ${count} inputs, ${failures} failures"
(( failures == 0 ))

#!/usr/bin/env bash
# msdeform --method=<name> for every registered method: each edits the
# cactus scenario (2 frames) and its report names the method; the handle of
# the methods that are not graphs (they hold it as a constraint) is exact; an
# unknown name is one line on stderr and exit 1, with no output written.
# The methods' own flags (rows of MethodOptionTable()) set their options, which
# the report records, and change the result; an out-of-range value is one line
# naming the flag.
#
#   bash tests/methods/cli_methods_test.sh <msdeform binary> <data folder>
set -euo pipefail
msdeform="$(realpath "$1")"
data="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
scenario="$(dirname "${data}")/experiments/scenarios/cactus.json"
if "${msdeform}" --quiet --scenario="${scenario}" --method=arap --out="${work}/arap.off" \
     2> "${work}/stderr"; then
  echo "cli_methods_test: --method=arap succeeded"; exit 1
fi
# One line naming the flag and the registered methods (the project's first).
expected="msdeform: --method=arap: expected multiscale, static, static_dense, cgal_arap, cgal_sr_arap, fastlsm, "
if [[ "$(wc -l < "${work}/stderr")" != 1 || "$(cat "${work}/stderr")" != "${expected}"* ]]; then
  echo "cli_methods_test: stderr was: $(cat "${work}/stderr")"; exit 1
fi
# Every registered method (the error above lists them) through the command line.
methods="$(sed -e 's/^.*expected //' -e 's/,//g' "${work}/stderr")"
for method in ${methods}; do
  "${msdeform}" --quiet --scenario="${scenario}" --frames=2 --method="${method}" \
    --out="${work}/${method}.off" --report="${work}/${method}.json"
  python3 - "${work}/${method}.json" "${method}" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
method = sys.argv[2]
assert report["method"] == method, (report["method"], method)
assert report["variables"] > 0, report["variables"]
if method not in ("multiscale", "static", "static_dense"):  # exact handles
    assert report["handle_rms"] == 0.0, report["handle_rms"]
    assert "scales" not in report  # not a graph method
PY
done
[[ ! -e "${work}/arap.off" ]] || { echo "cli_methods_test: wrote an output"; exit 1; }

# The methods' own flags: each sets its row (the report's options), and a
# changed value changes the mesh.
"${msdeform}" --quiet --scenario="${scenario}" --frames=2 --method=fastlsm --fastlsm_steps=3 \
  --fastlsm_region_half_width=1 --fastlsm_damping=0.25 --out="${work}/fastlsm_own.off"
"${msdeform}" --quiet --scenario="${scenario}" --frames=2 --method=cgal_sr_arap \
  --cgal_iterations=3 --cgal_tolerance=0.5 --cgal_sre_alpha=0.125 --out="${work}/cgal_own.off"
python3 - "${work}" <<'PY'
import json, sys
work = sys.argv[1]
fastlsm = json.load(open(f"{work}/fastlsm_own.json"))["options"]
cgal = json.load(open(f"{work}/cgal_own.json"))["options"]
expected = {"fastlsm.steps_per_frame": "3", "fastlsm.region_half_width": "1",
            "fastlsm.damping": "0.25"}
assert {k: fastlsm[k] for k in expected} == expected, fastlsm
expected = {"cgal.iterations": "3", "cgal.tolerance": "0.5", "cgal.sre_alpha": "0.125"}
assert {k: cgal[k] for k in expected} == expected, cgal
PY
if cmp -s "${work}/fastlsm.off" "${work}/fastlsm_own.off"; then
  echo "cli_methods_test: --fastlsm_* changed nothing"; exit 1
fi
if cmp -s "${work}/cgal_sr_arap.off" "${work}/cgal_own.off"; then
  echo "cli_methods_test: --cgal_* changed nothing"; exit 1
fi
for flag in fastlsm_steps=0 fastlsm_damping=1 fastlsm_region_half_width=9 cgal_iterations=0 \
            cgal_tolerance=-1 cgal_sre_alpha=nan; do
  method=fastlsm
  [[ "${flag}" == cgal_* ]] && method=cgal_sr_arap
  if "${msdeform}" --quiet --scenario="${scenario}" --method="${method}" --"${flag}" \
       --out="${work}/bad.off" 2> "${work}/stderr"; then
    echo "cli_methods_test: --${flag} succeeded"; exit 1
  fi
  message="$(cat "${work}/stderr")"
  if [[ "$(wc -l < "${work}/stderr")" != 1 || "${message}" != "msdeform: --${flag}: expected "* ]]; then
    echo "cli_methods_test: --${flag}: stderr was: $(cat "${work}/stderr")"; exit 1
  fi
done
echo "cli_methods_test: every registered method runs; an unknown one is refused;" \
  "the methods' own flags set their options"

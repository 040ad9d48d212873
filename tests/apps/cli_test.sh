#!/usr/bin/env bash
# The msdeform command line as a user meets it, each check with a known answer:
#   - --help, --helpshort and -h exit 0 and list msdeform's own flags by topic
#     (input first), not glog's; --version names the commit;
#   - a report repeats its run: --rerun gives the same mesh byte for byte, and
#     refuses once an input changed;
#   - outputs: default names carry the method (a graph method's energy and
#     solver too), the summary names the energy and a soft handle, an existing output is
#     replaced only with --overwrite, --out_frames writes every frame (the
#     last one equal to --out);
#   - a scenario's watch region gives leakage in the report; a scenario may
#     name a .sel/.def pair (the same mesh as --sel/--def on the command line);
#   - --polish writes the polished mesh, its energies in the report and one
#     line, repeats by --rerun, and its flags' bad values are one line naming
#     the flag (no output written); without it the report has no polish;
#   - a value not of its flag's type, and a flag the chosen method does not
#     read, are one line naming the flag (no output written);
#   - --help lists an option once with its other spellings, doubles shortest.
#
#   bash tests/apps/cli_test.sh <msdeform binary> <corpus folder> <data folder>
set -euo pipefail
msdeform="$(realpath "$1")"
corpus="$(cd "$2" && pwd)"
data="$(cd "$3" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
cd "${work}"
fail() { echo "cli_test: $*"; exit 1; }

# Help and version.
for flag in --help --helpshort -h; do
  "${msdeform}" "${flag}" > help.txt || fail "${flag} exited $?"
  grep -q '^input:' help.txt || fail "${flag}: no input section"
  grep -q -- '--max_iterations (int32, default 20)' help.txt || fail "${flag}: no --max_iterations"
  [[ "$(grep -n '^input:' help.txt | cut -d: -f1)" -lt "$(grep -n '^method:' help.txt | cut -d: -f1)" ]] \
    || fail "${flag}: input flags are not listed first"
  ! grep -q -- '--logtostderr' help.txt || fail "${flag} lists glog's flags"
  # An option's other spellings are named once, under its first; doubles shortest.
  [[ "$(grep -c -- '^  --backend ' help.txt)" == 1 ]] || fail "${flag}: --backend not listed once"
  ! grep -q -- '^  --solver ' help.txt || fail "${flag}: lists --solver besides --backend"
  ! grep -q -- '^  --threads ' help.txt || fail "${flag}: lists --threads besides --num_threads"
  grep -q -- 'per-frame solver: gauss_newton or ceres .*(also --solver)' help.txt \
    || fail "${flag}: --backend does not name --solver"
  grep -q -- '--threshold_floor (double, default 0.1)$' help.txt \
    || fail "${flag}: $(grep -- '--threshold_floor' help.txt)"
  ! grep -q '0000000000' help.txt || fail "${flag}: a default printed to 17 digits"
done
"${msdeform}" --version > version.txt || fail "--version exited $?"
grep -q 'commit ' version.txt || fail "--version names no commit: $(cat version.txt)"

# Scenario with a watch region on the corpus bar.
cat > watch.json <<JSON
{
  "mesh": "${corpus}/bar.off",
  "fixed": [{"slab": {"axis": "x", "from": 0, "to": 0.05}}],
  "handle": {"slab": {"axis": "x", "from": 0.95, "to": 1}},
  "watch": {"slab": {"axis": "x", "from": 0, "to": 0.2}},
  "transform": {"translation_rel": [0, 0.1, 0]},
  "frames": 3
}
JSON
"${msdeform}" --quiet --scenario=watch.json --w_con=1000 --out=a.off --out_frames=frames
grep -q '"leakage_rel"' a.json || fail "no leakage in the report of a scenario with a watch region"
[[ -f frames/watch_0001.off && -f frames/watch_0002.off && -f frames/watch_0003.off ]] \
  || fail "--out_frames did not write three frames: $(ls frames)"
cmp -s frames/watch_0003.off a.off || fail "the last frame differs from --out"
grep -q "\"sha256\": \"$(sha256sum "${corpus}/bar.off" | cut -d' ' -f1)\"" a.json \
  || fail "the report lacks the mesh's sha256"

# The report repeats the run, bit for bit.
"${msdeform}" --quiet --rerun=a.json --out=b.off
cmp -s a.off b.off || fail "--rerun gave a different mesh"
# An existing output is kept unless --overwrite.
if "${msdeform}" --quiet --rerun=a.json --out=b.off 2> err.txt; then fail "replaced b.off"; fi
grep -q 'exists; pass --overwrite' err.txt || fail "unclear refusal: $(cat err.txt)"
"${msdeform}" --quiet --rerun=a.json --out=b.off --overwrite || fail "--overwrite refused"
# A changed input is caught.
sed 's/"frames": 3/"frames": 2/' watch.json > changed.json && mv changed.json watch.json
if "${msdeform}" --quiet --rerun=a.json --out=c.off 2> err.txt; then fail "rerun ignored a changed input"; fi
grep -q 'changed since the report' err.txt || fail "unclear rerun error: $(cat err.txt)"
[[ ! -e c.off ]] || fail "a failed rerun left c.off"

# Default output names carry the method, a graph method's energy and solver; the summary
# names the energy, says where the handle is soft, and counts one frame as one.
"${msdeform}" --quiet --scenario=watch.json --solver=ceres
[[ -f msdeform_out/watch_multiscale_ed_ceres.off && -f msdeform_out/watch_multiscale_ed_ceres.json ]] \
  || fail "default outputs: $(ls msdeform_out)"
"${msdeform}" --scenario=watch.json > ed.txt
"${msdeform}" --scenario=watch.json --energy=arap > arap.txt || fail "the arap run was refused"
"${msdeform}" --scenario=watch.json --method=cgal_arap --frames=1 > cgal.txt
[[ -f msdeform_out/watch_multiscale_ed_gauss_newton.off && \
   -f msdeform_out/watch_multiscale_arap_gauss_newton.off && -f msdeform_out/watch_cgal_arap.off ]] \
  || fail "default outputs: $(ls msdeform_out)"
grep -q '^msdeform: watch (.*), multiscale method, ed energy, gauss_newton solver: ' ed.txt \
  || fail "summary: $(head -1 ed.txt)"
grep -q 'targets; under the ed energy the handle is a soft constraint, weighed by --w_con=100)' \
  ed.txt || fail "no soft-handle note: $(sed -n 2p ed.txt)"
grep -q '^msdeform: watch (.*), multiscale method, arap energy, gauss_newton solver: ' arap.txt \
  || fail "summary: $(head -1 arap.txt)"
! grep -q 'soft constraint' arap.txt || fail "an exact handle called soft: $(sed -n 2p arap.txt)"
grep -q '^msdeform: watch (.*), cgal_arap method, arap energy: ' cgal.txt \
  || fail "summary: $(head -1 cgal.txt)"
grep -q '^  1 frame: ' cgal.txt || fail "one frame: $(sed -n 2p cgal.txt)"
python3 - msdeform_out/watch_cgal_arap.json msdeform_out/watch_multiscale_arap_gauss_newton.json \
  <<'PY' || fail "report's energy and solver"
import json, sys
cgal, arap = (json.load(open(path)) for path in sys.argv[1:])
assert cgal["energy"] == "arap" and cgal["solver"] is None, (cgal["energy"], cgal["solver"])
assert arap["energy"] == "arap" and arap["solver"] == "gauss_newton"
PY

# A scenario naming a .sel/.def pair is the command line's --sel/--def.
cat > pair_scenario.json <<JSON
{"mesh": "${data}/meshes/cactus.off", "sel": "${data}/meshes/cactus.sel",
 "def": "${data}/meshes/cactus.def", "frames": 2}
JSON
"${msdeform}" --quiet --scenario=pair_scenario.json --out=pair.off
"${msdeform}" --quiet --mesh="${data}/meshes/cactus.off" --sel="${data}/meshes/cactus.sel" \
  --def="${data}/meshes/cactus.def" --frames=2 --out=flags.off
cmp -s pair.off flags.off || fail "scenario sel/def and --sel/--def differ"
# Polish on release (methods/polish.h).
"${msdeform}" --scenario=watch.json --polish --out=p.off > polish.txt
grep -q '^  polish: ARAP energy .* -> .* in [0-9]* iterations' polish.txt \
  || fail "--polish printed no polish line: $(cat polish.txt)"
python3 - p.json a.json <<'PY' || fail "--polish report"
import json, sys
report = json.load(open(sys.argv[1]))
polish = report["polish"]
assert polish["energy_after"] <= polish["energy_start"], polish
assert 0 < polish["iterations"] <= 30 and polish["setup_ms"] >= 0, polish
assert report["flags"]["polish"] == "true" and report["flags"]["polish_iterations"] == "30"
plain = json.load(open(sys.argv[2]))
assert "polish" not in plain and not any(k.startswith("polish") for k in plain["flags"]), plain
PY
"${msdeform}" --quiet --rerun=p.json --out=p2.off
cmp -s p.off p2.off || fail "--rerun of a polished run gave a different mesh"
while IFS='|' read -r flags message; do
  # shellcheck disable=SC2086
  if "${msdeform}" --quiet --scenario=watch.json ${flags} --out=bad.off 2> err.txt; then
    fail "${flags} was accepted"
  fi
  [[ "$(cat err.txt)" == "msdeform: ${message}" ]] || fail "${flags}: got '$(cat err.txt)'"
  [[ ! -e bad.off ]] || fail "${flags} wrote an output"
done <<'CASES'
--polish --polish_iterations=-1|--polish_iterations=-1: expected an integer in 0..1000000
--polish --polish_time_ms=-5|--polish_time_ms=-5: expected a number >= 0 (0: no limit)
--polish --polish_tolerance=2|--polish_tolerance=2: expected a number in [0, 1]
--polish --polish_anderson_window=51|--polish_anderson_window=51: expected an integer in 0..50
--polish_iterations=5|--polish_iterations=5 needs --polish
--w_con=abc|--w_con=abc: expected a number
--max_iterations=2.5|--max_iterations=2.5: expected an integer
--polish=maybe|--polish=maybe: expected true or false
--method=cgal_arap --w_con=5|--w_con=5: not an option of the cgal_arap method (an option of multiscale, static, static_dense)
--method=cgal_arap --backend=ceres|--backend=ceres: not an option of the cgal_arap method (an option of multiscale, static, static_dense)
--method=fastlsm --seed=3|--seed=3: not an option of the fastlsm method (an option of multiscale, static, static_dense)
--method=multiscale --fastlsm_steps=3|--fastlsm_steps=3: not an option of the multiscale method (an option of fastlsm)
CASES
echo "cli_test: all checks passed"

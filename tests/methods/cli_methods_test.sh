#!/usr/bin/env bash
# msdeform --method=<name> for every registered method: each edits the
# cactus scenario (2 frames) and its report names the method; the handle of
# the methods that drive it (cgal_arap, cgal_sr_arap, fastlsm) is exact; an
# unknown name is one line on stderr and exit 1, with no output written.
#
#   bash tests/methods/cli_methods_test.sh <msdeform binary> <data folder>
set -euo pipefail
msdeform="$(realpath "$1")"
data="$(cd "$2" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
scenario="$(dirname "${data}")/experiments/scenarios/cactus.json"
for method in multiscale static static_dense cgal_arap cgal_sr_arap fastlsm; do
  "${msdeform}" --quiet --scenario="${scenario}" --frames=2 --method="${method}" \
    --out="${work}/${method}.off" --report="${work}/${method}.json"
  python3 - "${work}/${method}.json" "${method}" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
method = sys.argv[2]
assert report["method"] == method, (report["method"], method)
assert report["variables"] > 0, report["variables"]
if method in ("cgal_arap", "cgal_sr_arap", "fastlsm"):
    assert report["handle_rms"] == 0.0, report["handle_rms"]
    assert "scales" not in report  # not a graph method
PY
done
if "${msdeform}" --quiet --scenario="${scenario}" --method=arap --out="${work}/arap.off" \
     2> "${work}/stderr"; then
  echo "cli_methods_test: --method=arap succeeded"; exit 1
fi
expected="msdeform: --method=arap: expected multiscale, static, static_dense, cgal_arap, cgal_sr_arap, fastlsm"
if [[ "$(cat "${work}/stderr")" != "${expected}" ]]; then
  echo "cli_methods_test: stderr was: $(cat "${work}/stderr")"; exit 1
fi
[[ ! -e "${work}/arap.off" ]] || { echo "cli_methods_test: wrote an output"; exit 1; }
echo "cli_methods_test: every registered method runs; an unknown one is refused"

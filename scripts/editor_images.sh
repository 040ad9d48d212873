#!/usr/bin/env bash
# The editor's images in the documentation, drawn by the editor of this
# checkout (nothing placed by hand):
#   docs/images/editor.png   README.md, "Editor": msdeform's default edit
#       (data/scenarios/armadillo_claw.json) in the editor's first view (the
#       whole mesh from the side the handle faces; no camera set), with e' as
#       a colour map, the node classes and edges of the selected scale, and the
#       panels, in the default 1280 x 800 window.
# Where there is no display it runs the editor under xvfb-run (Mesa's software
# renderer). From the repository root, after building msdeform_editor:
#   bash scripts/editor_images.sh [build/apps/msdeform_editor]
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
editor="$(realpath "${1:-${root}/build/apps/msdeform_editor}")"
[[ -x "${editor}" ]] || { echo "editor_images: ${editor} is not executable" >&2; exit 2; }
run=("${editor}")
if [[ -z "${DISPLAY:-}" ]]; then
  command -v xvfb-run > /dev/null ||
    { echo "editor_images: no display and no xvfb-run (apt-get install xvfb)" >&2; exit 2; }
  run=(xvfb-run -a -s "-screen 0 1280x1024x24" "${editor}")
fi

work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
cat > "${work}/editor_png.json" <<JSON
[
  {"do": "open", "scenario": "${root}/data/scenarios/armadillo_claw.json"},
  {"do": "view", "overlay": "rigidity", "nodes": true, "edges": true, "ui": true},
  {"do": "screenshot", "path": "${root}/docs/images/editor.png", "ui": true}
]
JSON
"${run[@]}" --quiet --overwrite --script="${work}/editor_png.json"
echo "editor_images: wrote docs/images/editor.png"

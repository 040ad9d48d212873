#!/bin/bash
# Renders the paper's figures into paper_figures/out/ (see paper_figures/README.md).
#
#   bash paper_figures/make_figures.sh          # from the repository root, as root
#
# 1. installs the Debian packages it needs when missing (python3-vtk9, xvfb,
#    python3-matplotlib, python3-numpy, python3-pil),
# 2. builds msdeform and msdeform_figure_data in build/ (incrementally; SKIP_BUILD=1: not),
# 3. generates the figure data into paper_figures/data/ (skipped when present;
#    FORCE=1 regenerates), timing runs included when experiments/results/ has none,
#    and `msdeform_experiments --quick` / `--solver_lab --quick` previews when it has no
#    table2.csv / solvers.csv,
# 4. renders with VTK offscreen under xvfb-run and charts with matplotlib,
#    writing out/*.png and out/index.md.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
FIG="$ROOT/paper_figures"
BUILD="${MSDEFORM_BUILD:-$ROOT/build}"
PY=/usr/bin/python3   # Debian's python (the pyenv one on PATH lacks dist-packages)
cd "$ROOT"

# 1. Packages.
missing=()
$PY -c "import vtk" 2>/dev/null || missing+=(python3-vtk9)
$PY -c "import matplotlib" 2>/dev/null || missing+=(python3-matplotlib)
$PY -c "import numpy" 2>/dev/null || missing+=(python3-numpy)
$PY -c "import PIL" 2>/dev/null || missing+=(python3-pil)   # figlib.shrink_png
command -v xvfb-run >/dev/null || missing+=(xvfb xauth)
if [ ${#missing[@]} -gt 0 ]; then
  echo "make_figures: installing ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# 2. Executables (an incremental build: nothing to do when up to date) and meshes.
# SKIP_BUILD=1 builds nothing (a build folder shared with a running experiment: build
# msdeform_figure_data yourself first).
if [ "${SKIP_BUILD:-0}" != 1 ]; then
  [ -f "$BUILD/CMakeCache.txt" ] || cmake -S "$ROOT" -B "$BUILD"
  cmake --build "$BUILD" -j2 --target msdeform msdeform_figure_data
  # The experiment runner, for a --quick preview of the tables experiments/results/ lacks.
  if [ ! -f "$ROOT/experiments/results/table2.csv" ] || \
     [ ! -f "$ROOT/experiments/results/solvers.csv" ]; then
    cmake --build "$BUILD" -j2 --target run_experiments || \
      echo "make_figures: msdeform_experiments did not build; charts from it are skipped"
  fi
fi
if [ ! -f "$ROOT/data/meshes/armadillo.off" ]; then
  bash "$ROOT/data/fetch_meshes.sh"
fi
if [ ! -f "$ROOT/data/meshes/armadillo_416k.off" ] && [ -x "$BUILD/apps/msdeform_make_large" ]; then
  "$BUILD/apps/msdeform_make_large"
fi

# 3. Data.
export MSDEFORM_BIN="$BUILD/apps/msdeform" FIGDATA_BIN="$BUILD/apps/msdeform_figure_data"
export EXPERIMENTS_BIN="$BUILD/experiments/msdeform_experiments"
bash "$FIG/generate_data.sh"

# 4. Render.
mkdir -p "$FIG/out"
xvfb-run -a -s "-screen 0 1600x1200x24" $PY "$FIG/render.py"
$PY "$FIG/charts.py"
$PY "$FIG/write_index.py"
echo "make_figures: wrote $(ls "$FIG"/out/*.png | wc -l) figures and out/index.md"

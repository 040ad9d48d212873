# Sourced by the table scripts of bench/: sets OUT, the folder for raw outputs (reports,
# /usr/bin/time logs, profiles): $PERF_OUT if set (kept), else a temporary folder removed on exit.
if [[ -n "${PERF_OUT:-}" ]]; then
  OUT=$PERF_OUT
  mkdir -p "$OUT"
else
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi

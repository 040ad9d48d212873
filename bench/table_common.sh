# Sourced by the table scripts of bench/ (performance_table.sh, scaling_table.sh).
#
# OUT: the folder for raw outputs (reports, /usr/bin/time logs, profiles): $PERF_OUT if set
# (kept, and reusable: runs replace what an earlier run left there), else a temporary folder
# removed on exit.
if [[ -n "${PERF_OUT:-}" ]]; then
  OUT=$PERF_OUT
  mkdir -p "$OUT"
else
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi

# timed_msdeform NAME ARGS...: msdeform ARGS under /usr/bin/time -v, its stderr (and the
# timing) in $OUT/NAME.time, outputs that exist replaced; a failure stops the script with
# msdeform's message.
timed_msdeform() {
  local name=$1
  shift
  if ! /usr/bin/time -v "$BUILD/apps/msdeform" "$@" --overwrite 2> "$OUT/$name.time"; then
    echo "msdeform failed ($name): $(grep -m1 '^msdeform' "$OUT/$name.time" || tail -n 1 "$OUT/$name.time")" >&2
    exit 1
  fi
}

# shellcheck shell=bash
# Sourced by the scripts: `phase NAME COMMAND...` runs COMMAND and says how long it took.
# The outermost script (demo.sh, test.sh, or build.sh/fuzz.sh run alone) lists every phase
# of its run with its time when it ends, done or failed, its sub-scripts' phases included,
# so a slow first run shows where the minutes went (issue 30: the demo's first value within
# 5 minutes and test.sh within 20 on a fresh 2-core machine).

if [ -z "${UNIMA_PHASE_REPORT:-}" ]; then
  UNIMA_PHASE_REPORT=$(mktemp "${TMPDIR:-/tmp}/unima-phases-XXXXXX")
  export UNIMA_PHASE_REPORT
  phase_owner=1
  phase_script_start=$SECONDS
  trap phase_summary EXIT
fi

phase() {  # name, command...
  local name=$1 start=$SECONDS status=0
  shift
  echo "== $name" >&2
  "$@" || status=$?
  local took=$((SECONDS - start))
  printf '   %-16s %5d s%s\n' "$name" "$took" "$([ "$status" -eq 0 ] || echo "  (failed, status $status)")" \
    >>"$UNIMA_PHASE_REPORT"
  echo "== $name: $took s" >&2
  return "$status"
}

# Lists the phases and the whole time; only the script that started the report does.
phase_summary() {
  [ -n "${phase_owner:-}" ] && [ -f "$UNIMA_PHASE_REPORT" ] || return 0
  {
    echo "== phases of ${0##*/}:"
    cat "$UNIMA_PHASE_REPORT"
    printf '   %-16s %5d s\n' total $((SECONDS - phase_script_start))
  } >&2
  rm -f "$UNIMA_PHASE_REPORT"
}

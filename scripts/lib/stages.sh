# Sourced by scripts/demo, scripts/test and .ci/run: named stages, each timed as it ends, and a table
# of them all when the script exits.
#
#   stage NAME COMMAND...   runs COMMAND, prints "== stage: NAME: N s, exit RC", returns RC
#
# The table ("== stage durations of SCRIPT (total N s)", one line per stage) is printed by an EXIT trap that
# sourcing this file sets, so it appears however the script ends.
stages=()

stage() {
  local name=$1 start=$SECONDS rc
  shift
  echo "== stage: $name"
  "$@"
  rc=$?
  local took=$((SECONDS - start))
  echo "== stage: $name: ${took} s, exit $rc"
  stages+=("$(printf '%-58s %5d s  %s' "$name" "$took" "$([[ $rc == 0 ]] && echo ok || echo "FAILED ($rc)")")")
  return "$rc"
}

stage_summary() {
  ((${#stages[@]} > 0)) || return 0
  echo "== stage durations of $(basename "$0") (total ${SECONDS} s)"
  printf '%s\n' "${stages[@]}"
}
trap stage_summary EXIT

# restarted.sh - sourced by the tests that restart a run, to check that the restart continued from its
# checkpoint (a run from the start gives the same bits, so comparing with the uninterrupted run cannot tell):
#   checkpoint_at FILE   where checkpoint FILE was taken: "K at" (after load step K) or "K within" (within
#                        load step K + 1), from its attributes /load_step and /within_load_step
#   restarted_from DIR   the same from DIR/summary.json's restarted_from; "none" for a fresh run, "?" when
#                        there is no readable summary.json
checkpoint_at() {
  local v
  v=$(h5dump -a /load_step -a /within_load_step "$1" 2>/dev/null | sed -n 's/ *(0): //p' | paste -sd' ')
  case "$v" in
    *" 1") echo "${v% *} within" ;;
    *" 0") echo "${v% *} at" ;;
    *) echo "no checkpoint ($1)" ;;
  esac
}
restarted_from() {
  /usr/bin/python3 -c '
import json, sys
r = json.load(open(sys.argv[1]))["restarted_from"]
print("none" if r is None else "%d %s" % (r["load_steps_done"], "within" if r["within_load_step"] else "at"))' \
    "$1/summary.json" 2>/dev/null || echo "?"
}

# kill_run.sh - sourced by the tests that kill a run midway (restart_every.sh, break_locate.sh, restart_static.sh,
# restart_newton.sh):
#   wait_for PID COND   poll the shell test COND every 0.01 s until it holds (status 0) or the run PID has
#                       ended or 60 s have passed (status 1)
#   kill_run PID        SIGKILL to mpiexec (PID) and its ranks, then wait until every rank is gone
#   term_ranks PID      SIGTERM to the ranks of mpiexec (PID), as a batch system signals every process of the job;
#                       waits for mpiexec and every rank; status: mpiexec's
#   attr FILE NAME...   the values of the attributes /NAME... of checkpoint FILE, in one h5dump (checkpoints are
#                       renamed into place, so the values are of one checkpoint), separated by spaces
wait_for() {
  local pid="$1" i
  for ((i = 0; i < 6000; i++)); do
    eval "$2" && return 0
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.01
  done
  return 1
}
kill_run() {
  local pid="$1" ranks p
  ranks=$(ps -o pid= --ppid "$pid")
  kill -KILL $ranks "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  for p in $ranks; do while kill -0 "$p" 2>/dev/null; do sleep 0.05; done; done
}
term_ranks() {
  local pid="$1" ranks p rc
  ranks=$(ps -o pid= --ppid "$pid")
  kill -TERM $ranks 2>/dev/null
  wait "$pid"; rc=$?
  for p in $ranks; do while kill -0 "$p" 2>/dev/null; do sleep 0.05; done; done
  return $rc
}
attr() {
  local f="$1" a=() n; shift
  for n in "$@"; do a+=(-a "$n"); done
  h5dump "${a[@]}" "$f" 2>/dev/null | sed -n 's/ *(0): //p' | paste -sd' '
}

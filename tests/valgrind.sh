#!/usr/bin/env bash
# valgrind.sh VALGRIND FABRIC SCENE SUPPRESSIONS: memcheck on a short strip run (20 mm x 5 mm,
# 2 load steps, frames written), on 1 rank and on 2 ranks under mpiexec: no invalid read or
# write, no use of uninitialised memory, no memory definitely or possibly lost at exit. SUPPRESSIONS names only Open MPI, PMIx and hwloc libraries
# (docs/reliability.md). --keep-debuginfo: Open MPI unloads its components at MPI_Finalize,
# and the leak report at exit must still know which library a frame was in.
set -u
valgrind="$1"; fabric="$2"; scene="$3"; supp="$4"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
vg=("$valgrind" --error-exitcode=1 --suppressions="$supp" --keep-debuginfo=yes --num-callers=40
    --leak-check=full --show-leak-kinds=definite,possible --errors-for-leak-kinds=definite,possible)
run=(-scene "$scene" -gauge_mm 20 -width_mm 5 -load_steps 2 -quiet)
fail=0
for np in 1 2; do
  launch=(); ((np > 1)) && launch=(mpiexec -n "$np")
  "${launch[@]}" "${vg[@]}" --log-file="$work/np$np.%p.log" "$fabric" "${run[@]}" -output_dir "$work/out$np" >"$work/np$np.out" 2>&1
  rc=$?
  # one log per rank that ran to its end (a singleton's MPI_Init also forks a process that
  # execs orted: valgrind's log of it stops at the exec, without a summary)
  mapfile -t logs < <(grep -l "ERROR SUMMARY" "$work"/np$np.*.log 2>/dev/null)
  clean=$(grep -l "ERROR SUMMARY: 0 errors" "${logs[@]}" 2>/dev/null | wc -l)
  if [[ $rc -eq 0 && ${#logs[@]} -eq $np && $clean -eq $np && -s "$work/out$np/summary.json" ]]; then
    echo "PASS $np rank(s): 0 errors, no leak; per process:"
    grep -h "ERROR SUMMARY\|total heap usage" "${logs[@]}" | sed 's/^==[0-9]*== */  /'
  else
    echo "FAIL $np rank(s): exit $rc, $clean of $np processes with 0 errors"
    cat "$work/np$np.out" "$work"/np$np.*.log
    fail=1
  fi
done
exit $fail

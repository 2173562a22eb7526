#!/usr/bin/env bash
# mpi_error.sh FABRIC SCENE: a PETSc option that asks MPI for what it cannot do (-sf_type window:
# Open MPI 4.1 here has no one-sided window for it) stops the run with one line that names the
# option, a non-zero exit and no output, not an MPI abort without a word of why. An MPI that runs
# it passes too (then the run must end normally, with the curve of a run without the option, bit
# for bit). The line comes once, not once per rank.
set -u
fabric="$1"
scene="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
log="$(cd "$work" && timeout 60 mpiexec -n 2 "$fabric" -scene "$scene" -quiet -load_steps 2 -output_dir "$work/out" \
  -sf_type window 2>&1)"
rc=$?
echo "$log" | head -3
if [[ $rc -eq 0 ]]; then
  [[ -f "$work/out/summary.json" ]] || { echo "FAIL: exit 0 without summary.json"; exit 1; }
  mpiexec -n 2 "$fabric" -scene "$scene" -quiet -load_steps 2 -output_dir "$work/ref" >/dev/null 2>&1 ||
    { echo "FAIL: the run without -sf_type window failed"; exit 1; }
  cmp -s "$work/out/curve.csv" "$work/ref/curve.csv" ||
    { echo "FAIL: this MPI runs -sf_type window, but its curve.csv differs from the run without it"; exit 1; }
  echo "PASS: this MPI runs -sf_type window, to the curve of the run without it"
  exit 0
fi
fail=0
((rc == 124)) && { echo "FAIL: timed out (a hang)"; fail=1; }
lines=$(grep -Ec '^fabric: error: MPI error .*\(with -sf_type window: this MPI may not run it' <<<"$log")
((lines == 1)) || { echo "FAIL: $lines 'fabric: error:' lines naming -sf_type window, expected one"; fail=1; }
[[ -e "$work/out" ]] && { echo "FAIL: output directory created"; fail=1; }
((fail == 0)) && echo "PASS: exit $rc, one line names -sf_type window, no output"
exit $fail

#!/usr/bin/env bash
# expect_pass.sh REGEX COMMAND...: a run that must succeed: exit code 0, its output (stdout and
# stderr) matching REGEX (grep -E), and no error (no "fabric: error" line, no PETSc traceback).
# CTest's PASS_REGULAR_EXPRESSION alone ignores the exit code: a run that printed its end line and
# then failed in PetscFinalize passed.
set -u
regex="$1"
shift
log="$("$@" 2>&1)"
rc=$?
echo "$log" | tail -5
fail=0
((rc == 0)) || { echo "FAIL: exit code $rc, expected 0"; fail=1; }
grep -Eq -- "$regex" <<<"$log" || { echo "FAIL: no line matches: $regex"; fail=1; }
! grep -Eq 'fabric: error|PETSC ERROR' <<<"$log" || { echo "FAIL: an error beside the run's output"; fail=1; }
((fail == 0)) && echo "PASS: exit 0, the output matches, no error"
exit $fail

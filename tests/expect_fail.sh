#!/usr/bin/env bash
# expect_fail.sh REGEX COMMAND...: bad input must give a clear message, a non-zero exit and no
# output. The message is the one line "fabric: error: ..." and must match REGEX, with no PETSc traceback. The command runs
# in an empty directory and gets "-output_dir DIR" appended unless it names its own -output_dir;
# afterwards that directory must not exist (unless it did before) and the working directory must
# still be empty (no default results/SCENE, no stray file).
set -u
regex="$1"
shift
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir "$work/cwd"
args=("$@")
out="$work/out"
given=0
for ((k = 0; k < ${#args[@]}; k++)); do
  if [[ ${args[k]} == -output_dir ]]; then
    given=1
    out="${args[k + 1]:-}"
  fi
done
((given)) || args+=(-output_dir "$out")
existed=0
[[ -n "$out" && -e "$out" ]] && existed=1
log="$(cd "$work/cwd" && "${args[@]}" 2>&1)"
rc=$?
echo "$log" | head -5
fail=0
if [[ $rc -eq 0 ]]; then
  echo "FAIL: exit code 0, expected non-zero"
  fail=1
fi
if ! grep '^fabric: error: ' <<<"$log" | grep -Eq -- "$regex"; then
  echo "FAIL: no 'fabric: error:' line matches: $regex"
  fail=1
fi
if grep -q 'PETSC ERROR' <<<"$log"; then
  echo "FAIL: PETSc's traceback (PETSC ERROR lines) beside the message"
  fail=1
fi
if ((!existed)) && [[ -n "$out" && -e "$out" ]]; then
  echo "FAIL: output directory $out was created"
  fail=1
fi
if [[ -n "$(ls -A "$work/cwd")" ]]; then
  echo "FAIL: left behind in the working directory: $(ls -A "$work/cwd")"
  fail=1
fi
((fail == 0)) && echo "PASS: exit $rc, message names the problem, no output left behind"
exit $fail

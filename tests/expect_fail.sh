#!/usr/bin/env bash
# expect_fail.sh REGEX COMMAND...: bad input must give a clear message, a non-zero exit
# and no output. The command gets "-output_dir DIR" appended; DIR must not exist after.
set -u
regex="$1"; shift
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
out="$work/out"
log="$("$@" -output_dir "$out" 2>&1)"; rc=$?
echo "$log" | head -5
fail=0
if [[ $rc -eq 0 ]]; then echo "FAIL: exit code 0, expected non-zero"; fail=1; fi
if ! grep -Eq -- "$regex" <<<"$log"; then echo "FAIL: message does not match: $regex"; fail=1; fi
if [[ -e "$out" ]]; then echo "FAIL: output directory was created"; fail=1; fi
((fail == 0)) && echo "PASS: exit $rc, message names the problem, no output left behind"
exit $fail

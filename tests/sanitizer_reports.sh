#!/usr/bin/env bash
# sanitizer_reports.sh DIR: the last test of the sanitizer build (docs/reliability.md). Every
# AddressSanitizer or UndefinedBehaviorSanitizer report of the tests before it is a file
# DIR/<test>.<pid>; fails, printing each, if there is any.
set -u
dir="$1"
shopt -s nullglob
reports=("$dir"/*)
if ((${#reports[@]} == 0)); then echo "PASS no sanitizer report"; exit 0; fi
for r in "${reports[@]}"; do
  t="$(basename "$r")"
  echo "=== test ${t%.*} (process ${t##*.}):"
  cat "$r"
  # GCC's UndefinedBehaviorSanitizer writes its message ("runtime error: ...") to stderr only;
  # it then aborts, and this file is AddressSanitizer's report of that abort
  if grep -q "__ubsan_handle_" "$r"; then
    echo "(undefined behaviour: its kind is in the __ubsan_handle_* frame, its place in the frame below;"
    echo " the \"runtime error\" message is in the test's output, unless the test script discards it)"
  fi
done
echo "FAIL ${#reports[@]} sanitizer report(s), from the tests: $(for r in "${reports[@]}"; do t="$(basename "$r")"; echo "${t%.*}"; done | sort -u | tr '\n' ' ')"
exit 1

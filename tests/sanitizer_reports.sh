#!/usr/bin/env bash
# sanitizer_reports.sh DIR: the last test of the sanitizer build (docs/reliability.md). Every
# AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer report of the tests before it
# is a file DIR/<test>.<pid>; fails, printing each, if there is any.
set -u
dir="$1"
shopt -s nullglob
reports=("$dir"/*)
if ((${#reports[@]} == 0)); then echo "PASS no sanitizer report"; exit 0; fi
for r in "${reports[@]}"; do
  t="$(basename "$r")"
  echo "=== test ${t%.*} (process ${t##*.}):"
  cat "$r"
done
echo "FAIL ${#reports[@]} sanitizer report(s), from the tests: $(for r in "${reports[@]}"; do t="$(basename "$r")"; echo "${t%.*}"; done | sort -u | tr '\n' ' ')"
exit 1

#!/usr/bin/env bash
# options_listed.sh FABRIC "NAMES": every option of FABRIC -help that takes numbers (its default is
# a number, a list of numbers, or unset) is in NAMES, the lists the input tests try NaN and Inf on
# (tests/CMakeLists.txt). A -warp_... option stands for its -weft_... twin too.
set -u
fabric="$1"
listed=" $2 "
help="$("$fabric" -help 2>&1)"
# the solver's options: from -test (the table's first) to the next line of dashes (then PETSc's own)
mapfile -t names < <(sed -n '/^  -test </,/^------/p' <<<"$help" |
  sed -nE 's/^  -([A-Za-z0-9_]+) <(-?[0-9][0-9.e+-]*(,-?[0-9][0-9.e+-]*)*|unset)>:.*/\1/p' | sort -u)
fail=0
count=0
for name in "${names[@]}"; do
  for o in "$name" $([[ $name == warp_* ]] && echo "weft_${name#warp_}"); do
    count=$((count + 1))
    if [[ "$listed" != *" $o "* && "$listed" != *" $o="* ]]; then
      echo "FAIL: -$o takes numbers but is not in the NaN/Inf input tests (tests/CMakeLists.txt)"
      fail=1
    fi
  done
done
if ((count < 40)); then echo "FAIL: only $count numeric options found in -help (has its format changed?)"; fail=1; fi
((fail == 0)) && echo "PASS: all $count numeric options of -help have NaN and Inf input tests"
exit $fail

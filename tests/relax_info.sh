#!/usr/bin/env bash
# relax_info.sh FABRIC INPUTS: -info's line for a relaxation round still going at its te step 1024, 2048, ...
# (RelaxInfo, src/balance.c: what holds a long round) and the line that ends each round (RelaxRound), on the
# square net (inputs/square_net.yaml, 23 x 23 free crossings, rounds of a few thousand te steps):
#  - the same lines on 1 and 3 ranks (the speed, residual and counts come from reductions);
#  - each RelaxInfo line is consistent: the fastest crossing is a free one (1 to 23 in i and j), the crossings
#    faster than -speed_tol number 1 to 529 when the speed is above it and 0 when not, and the shares of
#    sum |v|^2 along x, y and z add up to 1 (within the 0.015 of three 2-digit roundings);
#  - the RelaxRound lines' te steps add up to summary.json's te_steps (no tear here), one line a load step.
set -u
fabric="$1"; inputs="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail
for np in 1 3; do
  mpiexec -n $np "$fabric" -scene "$inputs/square_net.yaml" -quiet -output_dir "$work/n$np" -output_every 0 -info :sys \
    >"$work/info$np" 2>&1 || { cat "$work/info$np"; echo "FAIL the run on $np ranks failed"; exit 1; }
done
"$py" - "$work" <<'PY' || fail=1
import json, re, sys
d = sys.argv[1]
def lines(np, what):
    return [l.split("> ", 1)[1] for l in open(f"{d}/info{np}") if l.startswith("[0] <sys> " + what + "()")]
bad = 0
def check(ok, what):
    global bad
    print(("PASS " if ok else "FAIL ") + what); bad |= not ok
info1, info3 = lines(1, "RelaxInfo"), lines(3, "RelaxInfo")
check(len(info1) >= 5 and info1 == info3, f"RelaxInfo: {len(info1)} lines on 1 rank, the same {len(info3)} on 3")
pat = re.compile(r"residual (\S+), speed (\S+) m/s \(-speed_tol (\S+)\), the fastest at crossing \((\d+), (\d+)\); "
                 r"(\d+) free crossings faster than -speed_tol; sum \|v\|\^2 along x (\S+), y (\S+), z (\S+)")
wrong = []
for l in info1:
    m = pat.search(l)
    if not m:
        wrong.append(l); continue
    res, speed, tol, i, j, fast, sx, sy, sz = m.groups()
    speed, tol, i, j, fast = float(speed), float(tol), int(i), int(j), int(fast)
    if not (1 <= i <= 23 and 1 <= j <= 23 and (1 <= fast <= 529 if speed > tol else fast == 0)
            and abs(float(sx) + float(sy) + float(sz) - 1) <= 0.015):
        wrong.append(l)
check(not wrong, "each RelaxInfo line consistent (a free crossing the fastest, the count against -speed_tol, the shares add up to 1)"
      + ("" if not wrong else f": {wrong[:2]}"))
rounds = lines(1, "RelaxRound")
s = json.load(open(f"{d}/n1/summary.json"))
total = sum(int(re.search(r": (\d+) te steps", l).group(1)) for l in rounds)
check(len(rounds) == s["load_steps_done"] and total == s["te_steps"] and rounds == lines(3, "RelaxRound"),
      f"RelaxRound: {len(rounds)} lines for {s['load_steps_done']} load steps, {total} te steps (summary.json {s['te_steps']}), the same on 3 ranks")
sys.exit(bad)
PY
exit $fail

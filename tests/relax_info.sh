#!/usr/bin/env bash
# relax_info.sh FABRIC INPUTS: -info's line for a relaxation round still going at its te step 1024, 2048, ...
# (RelaxInfo, src/balance.c: what holds a long round) and the line that ends each round (RelaxRound):
#  - the square net (inputs/square_net.yaml, 23 x 23 free crossings, motion out of plane) and the bias specimen
#    (inputs/bias.yaml, motion in plane): the same lines on 1 and 3 ranks (the residual and speed are max-reductions,
#    the counts and the shares of sum |v|^2 exact sums);
#  - each RelaxInfo line at a te step 2^k >= 1024 below its round's count (RelaxRound of the same load step, round
#    and load factor), the shares along x, y and z adding up to 1 (within the 0.015 of three 2-digit roundings),
#    the crossings faster than -speed_tol at least 1 when the speed printed is above it and 0 when below; on the
#    square net the fastest a free crossing (1 to 23 in i and j) and the count at most 529;
#  - the RelaxRound lines' te steps add up to summary.json's te_steps (no tear here).
set -u
fabric="$1"; inputs="$2"
. "$(dirname "$0")/runs.sh" # $py, $work, $fail
for scene in square_net bias; do
  for np in 1 3; do
    mpiexec -n $np "$fabric" -scene "$inputs/$scene.yaml" -quiet -output_dir "$work/$scene$np" -output_every 0 -info :sys \
      >"$work/$scene$np.info" 2>&1 || { cat "$work/$scene$np.info"; echo "FAIL $scene: the run on $np ranks failed"; exit 1; }
  done
done
"$py" - "$work" <<'PY' || fail=1
import json, re, sys
d = sys.argv[1]
bad = 0
def check(ok, what):
    global bad
    print(("PASS " if ok else "FAIL ") + what); bad |= not ok
def lines(name, what):
    return [l.split("> ", 1)[1] for l in open(f"{d}/{name}.info") if l.startswith("[0] <sys> " + what + "()")]
pat = re.compile(r"load step (\d+), round (\d+) at load factor (\S+), te step (\d+) of the round: residual (\S+), speed (\S+) m/s "
                 r"\(-speed_tol (\S+)\), the fastest at crossing \((-?\d+), (-?\d+)\); (\d+) free crossings faster than "
                 r"-speed_tol; sum \|v\|\^2 along x (\S+), y (\S+), z (\S+)")
end = re.compile(r"load step (\d+), round (\d+) at load factor (\S+): (\d+) te steps")
for scene in ("square_net", "bias"):
    info1, info3 = lines(scene + "1", "RelaxInfo"), lines(scene + "3", "RelaxInfo")
    rounds1, rounds3 = lines(scene + "1", "RelaxRound"), lines(scene + "3", "RelaxRound")
    check(len(info1) >= 5 and info1 == info3 and rounds1 == rounds3,
          f"{scene}: {len(info1)} RelaxInfo and {len(rounds1)} RelaxRound lines on 1 rank, the same on 3")
    count = {}
    for l in rounds1:
        m = end.search(l)
        count.setdefault(m.group(1, 2, 3), int(m.group(4)))  # a round's first end line
    wrong = []
    for l in info1:
        m = pat.search(l)
        if not m:
            wrong.append(l); continue
        step, rnd, lf, n, res, speed, tol, i, j, fast, sx, sy, sz = m.groups()
        n, i, j, fast = int(n), int(i), int(j), int(fast)
        ok = n >= 1024 and n & (n - 1) == 0 and n < count.get((step, rnd, lf), 0)
        ok &= abs(float(sx) + float(sy) + float(sz) - 1) <= 0.015
        if speed != tol:  # printed to 3 digits: equal ones are not compared
            ok &= fast >= 1 if float(speed) > float(tol) else fast == 0
        if scene == "square_net":
            ok &= 1 <= i <= 23 and 1 <= j <= 23 and fast <= 529
        if not ok:
            wrong.append(l)
    check(not wrong, f"{scene}: each RelaxInfo line at a te step 2^k >= 1024 of a round that went on, its shares adding up "
          "to 1, its count of crossings faster than -speed_tol consistent with its speed" + ("" if not wrong else f": {wrong[:2]}"))
    s = json.load(open(f"{d}/{scene}1/summary.json"))
    total = sum(int(end.search(l).group(4)) for l in rounds1)
    check(total == s["te_steps"], f"{scene}: the RelaxRound lines' te steps {total}, summary.json's te_steps {s['te_steps']}")
sys.exit(bad)
PY
exit $fail

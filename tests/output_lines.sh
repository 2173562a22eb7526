#!/usr/bin/env bash
# output_lines.sh FABRIC INPUTS: what the explicit path prints and writes beside its curve, against curve.csv
# and values worked out apart from src/report.c (2 ranks):
#  1. a 20 x 60 mm strip (at 24 threads/cm 48 yarn spacings along, 144 yarns across: 49 x 144 crossings) in 6
#     load steps to 3 %, -max_inner_steps 270 (some load steps balance, some do not): each progress line has its
#     row's elongation, force, inner steps and residual (to the digits printed), a "*" after the inner steps
#     exactly when the row did not balance, and an ETA of the elapsed time x the load steps to go / the load steps
#     done (to the 0.1 s printed; 0.0 s at the end; the run takes some tenths of a second); the done line has the
#     te steps, the peak force and the elongations of summary.json and curve.csv, and says that some load steps
#     did not balance; summary.json: 2 ranks, grid 49 x 144, 7056 points, te_steps = the sum of inner_steps,
#     load_steps_done = 6, not converged;
#  2. a coarse ball burst test pushed 2 mm in 4 load steps: the progress lines' travel is curve.csv's travel_mm;
#     the force rises, so the maximum force is the last row's, at travel_at_max_force_mm = 2 (to 1e-9); no yarn
#     breaks, so there is no bursting_force_N;
#  3. a bias specimen (20 mm asked, 19.445436 mm on the grid's diagonals at 8 threads/cm): curve.csv's travel_mm
#     is the jaw's travel, elongation_pct / 100 x that gauge (to 1e-8 relative), and summary.json's gauge_mm is
#     the gauge on the grid, its width_mm the width there (10 mm asked, 10.606602 mm);
#  4. one warp yarn 200 mm long (481 crossings, 0.416667 mm apart) pulled to 20 % in 2 load steps: it breaks
#     through in load step 2 (rupture.sh: at 15.02 %); the first break's place is the middle of its segment from
#     the yarn's centre, x_mm = (i + 0.5 - 240) x 200 / 480, y_mm = 0 (to the 6 digits written), and its progress
#     line names that segment and place; the "ruptured" line has the force after, the maximum and where it was,
#     and the segments broken of summary.json; the done line says ruptured at the located break (15.02 %, within
#     0.01 %: load step 2's last row) with the maximum force at summary.json's elongation_at_max_force_pct;
#     summary.json's rupture is load step 2 at that row's elongation, with its force.
set -u
fabric="$1"; inputs="$2"
py=/usr/bin/python3
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
fail=0
mpiexec -n 2 "$fabric" -scene "$inputs/strip_warp.yaml" -gauge_mm 20 -width_mm 60 -load_steps 6 -elongation_pct 3 -predict none \
  -balance_tol 1e-5 -max_inner_steps 270 -output_every 0 -output_dir "$work/strip" >"$work/strip.log" 2>&1 \
  || { cat "$work/strip.log"; echo "FAIL the strip's run failed"; exit 1; }
"$py" - "$work/strip" "$work/strip.log" <<'PY' || fail=1
import csv, json, re, sys
d, log = sys.argv[1], open(sys.argv[2]).read()
rows = list(csv.DictReader(open(f"{d}/curve.csv")))
s = json.load(open(f"{d}/summary.json"))
bad = 0
def check(ok, what):
    global bad
    print(("PASS " if ok else "FAIL ") + what); bad |= not ok
pat = (r"load step +(\d+)/(\d+)  elongation +([0-9.]+) %  force +([0-9.-]+) N  N' +(\d+)([ *])  residual ([0-9.e+-]+)  "
       r"te [0-9.e+-]+ s  elapsed ([0-9.]+) s  ETA ([0-9.]+) s")
lines = re.findall(pat, log)
mix = sorted({r["balanced"] for r in rows}) == ["0", "1"]
check(len(lines) == len(rows) == 6 and mix, f"{len(lines)} progress lines, {len(rows)} rows, balanced and not: {[r['balanced'] for r in rows]}")
for l, r in zip(lines, rows):
    k, K, e, f, n, star, res, el, eta = int(l[0]), int(l[1]), float(l[2]), float(l[3]), int(l[4]), l[5], float(l[6]), float(l[7]), float(l[8])
    same = k == int(r["load_step"]) and abs(e - float(r["elongation_pct"])) <= 5e-4 and abs(f - float(r["force_N"])) <= 5e-5 \
        and n == int(r["inner_steps"]) and (star == "*") == (r["balanced"] == "0") \
        and abs(res - float(r["residual"])) <= 5e-3 * float(r["residual"])
    check(same, f"load step {k}: progress line {l[2]} %, {l[3]} N, {n}{star!r}, {l[6]} = row {r['elongation_pct']} %, "
          f"{r['force_N']} N, {r['inner_steps']}, balanced {r['balanced']}, {r['residual']}")
    want = el * (K - k) / k
    check(abs(eta - want) <= 0.05 + 0.05 * (K - k) / k + 1e-9, f"load step {k}: ETA {eta} s, elapsed {el} s x {K - k} / {k} = {want:.3f} s")
check(lines and lines[-1][8] == "0.0", f"the last progress line's ETA is 0.0 s: {lines[-1][8] if lines else None}")
done = re.search(r"fabric: done in [0-9.]+ s: (\d+) te steps, [0-9.e+-]+ point updates/s; peak force ([0-9.e+-]+) N"
                 r"(?: \(from a load step that did not balance\))?, "
                 r"last load step at ([0-9.e+-]+) % elongation \(maximum force at ([0-9.e+-]+) %\); (.*)", log)
check(done is not None, f"the done line: {done.group(0) if done else log.splitlines()[-2:]}")
if done:
    g = done.groups()
    check(int(g[0]) == s["te_steps"] and abs(float(g[1]) / s["max_force_N"] - 1) <= 5e-4
          and abs(float(g[2]) - float(rows[-1]["elongation_pct"])) <= 5e-4 * float(g[2])
          and abs(float(g[3]) - s["elongation_at_max_force_pct"]) <= 5e-4 * float(g[3])
          and g[4] == "some load steps did NOT balance (see curve.csv residual)",
          f"the done line: {g} vs te_steps {s['te_steps']}, max_force_N {s['max_force_N']}, last row {rows[-1]['elongation_pct']} %, "
          f"elongation_at_max_force_pct {s['elongation_at_max_force_pct']}")
inner = sum(int(r["inner_steps"]) for r in rows)
check(s["ranks"] == 2 and s["grid"] == [49, 144] and s["points"] == 7056 and s["te_steps"] == inner and s["load_steps_done"] == 6
      and s["converged"] is False and s["solver"] == "explicit",
      f"summary.json: ranks {s['ranks']}, grid {s['grid']}, points {s['points']}, te_steps {s['te_steps']} (rows: {inner}), "
      f"load_steps_done {s['load_steps_done']}, converged {s['converged']}, solver {s['solver']}")
sys.exit(bad)
PY

mpiexec -n 2 "$fabric" -scene "$inputs/pushing.yaml" -ends_per_cm 8 -picks_per_cm 8 -sphere_travel_mm 2 -load_steps 4 \
  -output_every 0 -output_dir "$work/push" >"$work/push.log" 2>&1 || { cat "$work/push.log"; echo "FAIL the pushing run failed"; exit 1; }
"$py" - "$work/push" "$work/push.log" <<'PY' || fail=1
import csv, json, re, sys
d, log = sys.argv[1], open(sys.argv[2]).read()
rows = list(csv.DictReader(open(f"{d}/curve.csv")))
s = json.load(open(f"{d}/summary.json"))
travel = [float(t) for t in re.findall(r"load step +\d+/4  travel +([0-9.-]+) mm", log)]
f = [float(r["force_N"]) for r in rows]
ok1 = len(travel) == len(rows) == 4 and all(abs(t - float(r["travel_mm"])) <= 5e-4 for t, r in zip(travel, rows))
print(("PASS" if ok1 else "FAIL") + f" progress lines' travel {travel} mm = curve.csv's {[r['travel_mm'] for r in rows]}")
ok2 = all(b > a for a, b in zip(f, f[1:])) and abs(s["travel_at_max_force_mm"] - 2) <= 1e-9 and s["max_force_N"] == f[-1]
ok2 = ok2 and s.get("rupture") is None and "bursting_force_N" not in s
print(("PASS" if ok2 else "FAIL") + f" the force rises {f}: maximum {s['max_force_N']} N at travel_at_max_force_mm "
      f"{s['travel_at_max_force_mm']} (2 mm, tol 1e-9); rupture {s.get('rupture')}, bursting_force_N {s.get('bursting_force_N')}")
sys.exit(0 if ok1 and ok2 else 1)
PY

mpiexec -n 2 "$fabric" -scene "$inputs/bias.yaml" -quiet -gauge_mm 20 -width_mm 10 -ends_per_cm 8 -picks_per_cm 8 -load_steps 2 \
  -output_every 0 -output_dir "$work/bias" >/dev/null || { echo "FAIL the bias run failed"; exit 1; }
"$py" - "$work/bias" <<'PY' || fail=1
import csv, json, sys
d = sys.argv[1]
gauge = 11 * 1.25 * 2 ** 0.5 # 20 mm on the grid's diagonals at 8 threads/cm: 11 diagonal steps of 1.25 mm
width = 6 * 1.25 * 2 ** 0.5 # 10 mm: 6 of them
rows = list(csv.DictReader(open(f"{d}/curve.csv")))
s = json.load(open(f"{d}/summary.json"))
err = max(abs(float(r["travel_mm"]) / (float(r["elongation_pct"]) / 100 * gauge) - 1) for r in rows)
ok = len(rows) == 2 and err <= 1e-8 and abs(s["gauge_mm"] - gauge) <= 5e-5 and abs(s["width_mm"] - width) <= 5e-5
print(("PASS" if ok else "FAIL") + f" bias: travel_mm = elongation x the gauge {gauge:.9g} mm within {err:.1e} (tol 1e-8); "
      f"summary.json gauge_mm {s['gauge_mm']}, width_mm {s['width_mm']} (expected {width:.6g})")
sys.exit(0 if ok else 1)
PY
mpiexec -n 2 "$fabric" -scene "$inputs/strip_warp.yaml" -yarns 1 -elongation_pct 20 -load_steps 2 -output_every 0 \
  -output_dir "$work/yarn" >"$work/yarn.log" 2>&1 || { cat "$work/yarn.log"; echo "FAIL the one yarn's run failed"; exit 1; }
"$py" - "$work/yarn" "$work/yarn.log" <<'PY' || fail=1
import csv, json, re, sys
d, log = sys.argv[1], open(sys.argv[2]).read()
rows = list(csv.DictReader(open(f"{d}/curve.csv")))
s = json.load(open(f"{d}/summary.json"))
b, r = s.get("first_break"), s.get("rupture")
bad = 0
def check(ok, what):
    global bad
    print(("PASS " if ok else "FAIL ") + what); bad |= not ok
check(b is not None and r is not None and s["grid"] == [481, 1], f"first break {b}, rupture {r}, grid {s['grid']}")
if b is None or r is None:
    sys.exit(1)
x = (b["i"] + 0.5 - 240) * 200 / 480
check(b["yarn"] == "warp" and b["j"] == 0 and abs(b["x_mm"] - x) <= 5e-6 * abs(x) and b["y_mm"] == 0 and b["load_step"] == 2,
      f"the first break's place: segment {b['i']},{b['j']} at {b['x_mm']}, {b['y_mm']} mm, the middle of its segment {x:.6g}, 0 mm")
m = re.search(r"load step +2/2 .*\n  first yarn break: (\w+) segment at crossing (\d+),(\d+) \(([0-9.-]+), ([0-9.-]+) mm from the centre\)", log)
check(m is not None and m.group(1) == b["yarn"] and int(m.group(2)) == b["i"] and int(m.group(3)) == b["j"]
      and abs(float(m.group(4)) - b["x_mm"]) <= 5e-3 and abs(float(m.group(5)) - b["y_mm"]) <= 5e-3,
      f"load step 2's first break line: {m.group(0).splitlines()[-1] if m else None}")
m = re.search(r"  ruptured: the force fell to ([0-9.e+-]+) N, below ([0-9.]+) % of its maximum ([0-9.e+-]+) N at ([0-9.e+-]+) % "
              r"elongation; (\d+) segments broken; the test ends", log)
check(m is not None and abs(float(m.group(1)) - r["force_N"]) <= 5e-4 * max(1, r["force_N"]) and m.group(2) == "10"
      and abs(float(m.group(3)) / s["max_force_N"] - 1) <= 5e-4 and abs(float(m.group(4)) / s["elongation_at_max_force_pct"] - 1) <= 5e-4
      and int(m.group(5)) == s["segments_broken"] == 480,
      f"the ruptured line: {m.group(0) if m else None}; summary.json: force {r['force_N']} N, maximum {s['max_force_N']} N at "
      f"{s['elongation_at_max_force_pct']} %, {s['segments_broken']} segments broken")
m = re.search(r"fabric: done in .*; peak force ([0-9.e+-]+) N(?: \(from a load step that did not balance\))?, ruptured at ([0-9.e+-]+) % elongation \(maximum force at ([0-9.e+-]+) %\)", log)
check(m is not None and abs(float(m.group(2)) - r["elongation_pct"]) <= 5e-3 and 15.02 <= r["elongation_pct"] <= 15.03
      and abs(float(m.group(3)) / s["elongation_at_max_force_pct"] - 1) <= 5e-4,
      f"the done line: {m.group(0) if m else None}")
check(r["load_step"] == 2 and r["elongation_pct"] == float(rows[-1]["elongation_pct"]) and r["force_N"] == float(rows[-1]["force_N"])
      and len(rows) == 2, f"summary.json's rupture {r}: load step 2 at the last row's {rows[-1]['elongation_pct']} % and force {rows[-1]['force_N']} N")
sys.exit(bad)
PY
exit $fail

#!/usr/bin/env bash
# -te_measure's records in summary.json against the states it measured (each printed by -info):
#  1. a state at a load step's end carries the te that load step ran with (its start's), not the
#     next load step's (the crimped strip's te falls 4-fold between load steps 2 and 3);
#  2. first, last, tightest (the smallest limit) and worst (the largest te / limit) are those of the
#     list of states, within the 6 digits printed;
#  3. the paper's scheme (-integrator paper) is stable to 1/omega_max, half the 2/omega_max of the
#     default FIRE (and of the damped scheme): at load step 1's start (the grips moved, no te step taken:
#     the same state for both) its limit is the FIRE run's / 2, within 1e-5;
#  4. a run that ruptures before its last load step measures its last state: `last` is the end of the
#     load step it ruptured in (-te_measure 100 measured only load step 1, and `last` named it).
set -u
fabric="$1"; inputs="$2"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$inputs/strip_warp.yaml" -yarns 4 -gauge_mm 10 -elongation_pct 12 -load_steps 6 -te_measure 1 -quiet)
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/d" -info :sys >"$work/log" 2>&1 || { cat "$work/log"; echo "FAIL the FIRE run"; exit 1; }
mpiexec -n 2 "$fabric" "${opts[@]}" -output_dir "$work/p" -integrator paper >"$work/paper.log" 2>&1 || { cat "$work/paper.log"; echo "FAIL the paper run"; exit 1; }
"$fabric" -scene "$inputs/strip_warp_rupture.yaml" -ends_per_cm 6 -picks_per_cm 5 -gauge_mm 20 -width_mm 10 -load_steps 8 \
  -te_measure 100 -quiet -output_dir "$work/r" >"$work/rupture.log" 2>&1 || { cat "$work/rupture.log"; echo "FAIL the rupture run"; exit 1; }
/usr/bin/python3 - "$work/log" "$work/d/summary.json" "$work/p/summary.json" "$work/r/summary.json" <<'PY'
import json, re, sys
states = [(int(m[1]), m[2], float(m[3]), float(m[4]))
          for m in re.finditer(r"\[0\] <sys> Measure\(\): load step (\d+) (start|end): te (\S+) s, stable bound \S+ s, measured limit (\S+) s",
                               open(sys.argv[1]).read())]
d, p = json.load(open(sys.argv[2]))["te_measure"], json.load(open(sys.argv[3]))["te_measure"]
rel = lambda a, b: abs(a - b) / abs(b)
fail = 0
def check(ok, what):
    global fail
    print(("PASS " if ok else "FAIL ") + what)
    fail |= not ok
start = {s[0]: s[2] for s in states if s[1] == "start"}
ends = [s for s in states if s[1] == "end"]
check(len(states) == d["states"] and len(set(start.values())) > 1 and all(s[0] in start and rel(s[2], start[s[0]]) < 1e-5 for s in ends),
      f"{len(states)} states, te {sorted(set(start.values()))} s: each load step's end has the te of its start")
def same(rec, s):
    return rec["load_step"] == s[0] and rec["at"] == s[1] and rel(rec["te_s"], s[2]) < 1e-5 and rel(rec["limit_s"], s[3]) < 1e-5
tight = min(s[3] for s in states)
worst = max(s[2] / s[3] for s in states)
check(same(d["first"], states[0]) and same(d["last"], states[-1]), "first and last are the first and last states")
check(rel(d["tightest"]["limit_s"], tight) < 1e-5 and rel(max(s[3] for s in states), tight) > 0.1,
      f"tightest: the smallest limit {tight:.6g} s of {min(s[3] for s in states):.6g} to {max(s[3] for s in states):.6g} s")
check(abs(d["worst"]["te_over_limit"] - worst) < 1e-4, f"worst: the largest te / limit {worst:.4f}")
r = p["first"]["limit_s"] / d["first"]["limit_s"]
check(p["first"]["load_step"] == 1 and p["first"]["at"] == "start" and abs(r - 0.5) < 1e-5 * 0.5,
      f"the paper scheme's limit at load step 1's start / FIRE's = {r:.7f} (1/omega_max vs 2/omega_max: 0.5)")
u = json.load(open(sys.argv[4]))
t = u["te_measure"]
check(u["load_steps_done"] < 8 and u["rupture"] is not None and t["states"] == 3 and t["last"]["load_step"] == u["load_steps_done"]
      and t["last"]["at"] == "end", f"ruptured at load step {u['load_steps_done']} of 8: last measured {t['last']['load_step']} {t['last']['at']}, {t['states']} states")
sys.exit(fail)
PY

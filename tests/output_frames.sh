#!/usr/bin/env bash
# output_frames.sh FABRIC SCENE: what the frames of fabric.h5 hold, against values worked out apart from
# src/frames.c (the 20 x 5 mm strip on 2 ranks; -grip_ramp_steps 0: the jaw jumps, so that the test time
# of a load step's states is its time_s in curve.csv):
#  1. -output_every 4 of 6 load steps: frames at load steps 0, 4 and 6 (the last, which is no multiple
#     of 4: the default -output_every is a tenth of the load steps, rounded up), each at its time_s and
#     te step = its inner_steps in curve.csv; in every frame displacement = positions - the rest
#     positions (exactly); frame 0 is the rest state: positions = rest positions, velocities 0; the end
#     line counts the 3 frames;
#  2. -output_te_every 1, -integrator damped, -te T: a te frame at te step n of load step k is at
#     time_s(k) + n T, the load step's own frame at time_s(k) + inner_steps T (to 1e-3 T); between
#     consecutive te frames of a load step every free crossing moved by T times the later frame's
#     velocity (the damped scheme's x += T v, to 1e-9 of the largest move); with -output_te_every 10 and 25 te
#     steps a load step, the frames are at te steps 10, 20 and 25 (the load step's own) of each;
#  3. a disc (square_net.yaml, -shape disc): point_kind is -1 at the crossings outside it, as many as the grid's
#     nx ny less summary.json's points;
#  4. memory held by frames: 600 more frames (1 rank, a frame every load step) raise the run's peak
#     resident memory by less than 4 MB (PETSc 3.18's VecView kept 20 KB a frame: 12 MB; measured
#     with the writer of src/frames.c, 0.1 MB); not measured in a build with AddressSanitizer, whose
#     freed memory is held back (240 MB more there).
set -u
fabric="$1"; scene="$2"
py=/usr/bin/python3
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
opts=(-scene "$scene" -quiet -gauge_mm 20 -width_mm 5 -elongation_pct 3 -predict none -grip_ramp_steps 0 -balance_tol 1e-4)
fail=0
mpiexec -n 2 "$fabric" "${opts[@]}" -load_steps 6 -output_every 4 -output_dir "$work/every" >"$work/every.log" || { echo "FAIL the run failed"; exit 1; }
"$py" - "$work/every" <<'PY' || fail=1
import csv, sys
import h5py, numpy as np
d = sys.argv[1]
rows = {int(r["load_step"]): r for r in csv.DictReader(open(f"{d}/curve.csv"))}
with h5py.File(f"{d}/fabric.h5", "r") as f:
    x0 = f["grid/rest_positions"][...]
    fr = [f["frames"][k] for k in sorted(f["frames"])]
    got = [(int(g.attrs["load_step"]), float(g.attrs["time_s"]), int(g.attrs["te_step"])) for g in fr]
    want = [(0, 0.0, 0)] + [(k, float(rows[k]["time_s"]), int(rows[k]["inner_steps"])) for k in (4, 6)]
    ok = [a[0] == b[0] and abs(a[1] - b[1]) <= 1e-9 * max(1, b[1]) and a[2] == b[2] for a, b in zip(got, want)]
    ok1 = len(got) == 3 and all(ok)
    print(("PASS" if ok1 else "FAIL") + f" -output_every 4 of 6: frames (load step, time_s, te step) {got}, expected {want}")
    bad = [k for k, g in enumerate(fr) if not np.array_equal(g["displacement"][...], g["positions"][...] - x0)]
    ok2 = not bad and np.abs(fr[-1]["displacement"][...]).max() > 0
    print(("PASS" if ok2 else "FAIL") + f" displacement = positions - rest positions in every frame" + (f" (not in frames {bad})" if bad else ""))
    ok3 = np.array_equal(fr[0]["positions"][...], x0) and not np.any(fr[0]["velocities"][...])
    print(("PASS" if ok3 else "FAIL") + " frame 0 is the rest state: positions = rest positions, velocities 0")
sys.exit(0 if ok1 and ok2 and ok3 else 1)
PY
grep -q "^fabric: results in $work/every/ (curve.csv, summary.json, fabric.h5 and fabric.xmf (3 frames))$" "$work/every.log" \
  && echo "PASS the end line counts the 3 frames" || { cat "$work/every.log"; echo "FAIL the end line does not count the 3 frames"; fail=1; }

T=2e-7
mpiexec -n 2 "$fabric" "${opts[@]}" -load_steps 2 -max_inner_steps 25 -integrator damped -te $T -output_every 1 \
  -output_te_every 1 -output_dir "$work/te" >/dev/null || { echo "FAIL the run with te frames failed"; exit 1; }
"$py" - "$work/te" $T <<'PY' || fail=1
import csv, sys
import h5py, numpy as np
d, T = sys.argv[1], float(sys.argv[2])
rows = {int(r["load_step"]): r for r in csv.DictReader(open(f"{d}/curve.csv"))}
with h5py.File(f"{d}/fabric.h5", "r") as f:
    free = f["grid/point_kind"][...].reshape(-1) == 0
    fr = [f["frames"][k] for k in sorted(f["frames"])][1:]
    at = [(int(g.attrs["load_step"]), int(g.attrs["te_step"]), float(g.attrs["time_s"])) for g in fr]
    err = max(abs(t - (float(rows[k]["time_s"]) + n * T)) / T for k, n, t in at)
    last = {k: max(n for kk, n, _ in at if kk == k) for k in rows}
    ok1 = len(at) == sum(int(r["inner_steps"]) for r in rows.values()) and all(last[k] == int(rows[k]["inner_steps"]) for k in rows)
    print(("PASS" if ok1 and err <= 1e-3 else "FAIL") + f" {len(at)} te frames of load steps {sorted(rows)}, each at time_s + n T: "
          f"largest difference {err:.1e} T (tol 1e-3 T)")
    worst, n = 0.0, 0
    for a, b, ga, gb in zip(at, at[1:], fr, fr[1:]):
        if a[0] != b[0] or b[1] != a[1] + 1:
            continue
        dx = (gb["positions"][...] - ga["positions"][...]).reshape(-1, 3)[free]
        v = gb["velocities"][...].reshape(-1, 3)[free]
        worst, n = max(worst, np.abs(dx - T * v).max() / np.abs(dx).max()), n + 1
    ok2 = n >= 40 and worst <= 1e-9
    print(("PASS" if ok2 else "FAIL") + f" {n} pairs of consecutive te frames: the free crossings moved by T v within {worst:.1e} "
          "of the largest move (tol 1e-9)")
sys.exit(0 if ok1 and err <= 1e-3 and ok2 else 1)
PY
mpiexec -n 2 "$fabric" "${opts[@]}" -load_steps 2 -max_inner_steps 25 -integrator damped -te $T -output_every 1 \
  -output_te_every 10 -output_dir "$work/te10" >/dev/null || { echo "FAIL the run with te frames every 10 failed"; exit 1; }
"$py" - "$work/te10" $T <<'PY' || fail=1
import csv, sys
import h5py
d, T = sys.argv[1], float(sys.argv[2])
time_s = {int(r["load_step"]): float(r["time_s"]) for r in csv.DictReader(open(f"{d}/curve.csv"))}
with h5py.File(f"{d}/fabric.h5", "r") as f:
    at = [(int(g.attrs["load_step"]), int(g.attrs["te_step"]), float(g.attrs["time_s"])) for g in (f["frames"][k] for k in sorted(f["frames"]))]
want = [(0, 0)] + [(k, n) for k in (1, 2) for n in (10, 20, 25)]
ok = [a[:2] for a in at] == want and all(abs(t - (time_s[k] + n * T)) <= 1e-3 * T for k, n, t in at[1:])
print(("PASS" if ok else "FAIL") + f" -output_te_every 10 of 25 te steps: frames (load step, te step) {[a[:2] for a in at]}, expected {want}, "
      "each at time_s + n T")
sys.exit(0 if ok else 1)
PY

mpiexec -n 2 "$fabric" -scene "$(dirname "$scene")/square_net.yaml" -quiet -shape disc -load_steps 1 -output_dir "$work/disc" >/dev/null || { echo "FAIL the disc's run failed"; exit 1; }
"$py" - "$work/disc" <<'PY' || fail=1
import json, sys
import h5py, numpy as np
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
with h5py.File(f"{d}/fabric.h5", "r") as f:
    kind = f["grid/point_kind"][...]
nx, ny = s["grid"]
absent = int(np.sum(kind == -1))
ok = kind.shape == (ny, nx) and absent == nx * ny - s["points"] > 0 and np.all(kind >= -1)
print(("PASS" if ok else "FAIL") + f" a disc on a {nx} x {ny} grid: point_kind -1 at {absent} crossings, "
      f"{nx} x {ny} - {s['points']} points = {nx * ny - s['points']}")
sys.exit(0 if ok else 1)
PY

peak() { # KB: the peak resident memory of a 1-rank run writing a frame at each of $1 load steps
  "$py" -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$fabric" "${opts[@]}" -load_steps "$1" -output_every 1 \
    -output_dir "$work/mem$1"
}
if ldd "$fabric" 2>/dev/null | grep -q libasan; then # AddressSanitizer holds freed memory back: no measure
  echo "SKIP the peak memory of 600 more frames: $fabric is built with AddressSanitizer"
  exit $fail
fi
m50=$(peak 50) && m650=$(peak 650) || { echo "FAIL the runs of 50 and 650 frames failed"; exit 1; }
if (( m650 - m50 < 4096 )); then
  echo "PASS 600 more frames raise the peak resident memory by $(( m650 - m50 )) KB ($m50 KB with 51 frames; limit 4096 KB)"
else
  echo "FAIL 600 more frames raise the peak resident memory by $(( m650 - m50 )) KB ($m50 KB with 51 frames; limit 4096 KB)"; fail=1
fi
exit $fail

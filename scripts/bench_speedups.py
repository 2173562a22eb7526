#!/usr/bin/python3
"""The measured trade of the speed-ups (MODEL.md 8-10): run by scripts/bench_speedups.sh.

Table 1: the strip tests (inputs/strip_warp.yaml, strip_weft.yaml, narrowed to 2 mm = 5 yarns
         so that plain multi-sampling is affordable; the strip's per-yarn response does not
         depend on its width) with every combination of the switches: configuration, wall
         time, te steps, point updates, and the largest force error along the curve in % of
         the peak force against a tight-tolerance reference, and whether every load step
         balanced. Plain multi-sampling (no early exit) uses the smallest fixed N that reaches
         1 % (found by a sweep, printed first).
Table 2: balance tolerance x te_safety sweep (early exit, no prediction; the speed tolerance
         is the test speed times balance_tol / 1e-3): error vs time, and
         results/bench/speedups_trade.png.
Table 3: a local load in a 2000 x 2000 fabric (inputs/local_2000.yaml): point updates with
         the front and sleeping vs the fraction of the fabric that actually moves.
The reference (linear prediction, -balance_tol 1e-8 -speed_tol 1e-8, up to 400 000 te steps
per load step) must balance every load step: one that does not stops the script (exit 1).
Options: --quick (smaller sweeps), --np N (ranks, default 1), --tables 1,2,3 (which to run).
Ctrl-C stops the current run (mpiexec and its ranks), removes the temporary outputs, exit 130.
"""
import argparse, csv, itertools, json, os, shutil, signal, struct, subprocess, sys, tempfile, time

from runstop import stop_run  # scripts/runstop.py


def tables(text):
    """--tables: a comma-separated list of 1, 2, 3"""
    t = text.split(",")
    if not t or any(x not in ("1", "2", "3") for x in t):
        raise argparse.ArgumentTypeError("%r: a comma-separated list of 1, 2, 3" % text)
    return t


def ranks(text):
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError("%r: a positive number of ranks" % text)
    return n


ap = argparse.ArgumentParser(prog="scripts/bench_speedups.sh", description="The measured trade of the speed-ups (MODEL.md 8-10): "
                             "prints three tables and writes results/bench/speedups_trade.png (about 15-25 minutes on 2 cores).")
ap.add_argument("--quick", action="store_true", help="smaller sweeps")
ap.add_argument("--np", type=ranks, default=1, help="ranks of each run (default 1)")
ap.add_argument("--tables", type=tables, default=["1", "2", "3"], help="which tables to run, e.g. 1,3 (default 1,2,3)")
ARGS = ap.parse_args()

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FABRIC = os.path.join(ROOT, "build", "fabric")
NP = ARGS.np
QUICK = ARGS.quick
TABLES = ARGS.tables
WORK = None  # the runs' outputs: a temporary directory, made once results/bench is known to be usable
OUT = os.path.join(ROOT, "results", "bench")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
_count = [0]


def run(scene, opts):
    """run fabric, return (curve rows, summary)"""
    _count[0] += 1
    out = os.path.join(WORK, "r%d" % _count[0])
    # the paper's speed-ups on the damped scheme, the paper's kind of relaxation (FIRE, the default: docs/relaxation.md)
    cmd = ["mpiexec", "-n", str(NP), FABRIC, "-scene", os.path.join(ROOT, "inputs", scene), "-output_dir", out, "-quiet", "-output_every", "0",
           "-integrator", "damped"] + opts
    # a session of its own: Ctrl-C reaches this script alone, which stops the run whole (stop_run)
    p = subprocess.Popen(cmd, env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        err = p.communicate()[1]
    except BaseException:
        signal.signal(signal.SIGINT, signal.SIG_IGN); signal.signal(signal.SIGTERM, signal.SIG_IGN)
        stop_run(p)
        raise
    if p.returncode != 0:
        sys.stderr.write(err)
        sys.exit("bench_speedups: this run stopped (exit %d), no table: %s" % (p.returncode, " ".join(cmd)))
    rows = list(csv.DictReader(open(os.path.join(out, "curve.csv"))))
    return rows, json.load(open(os.path.join(out, "summary.json")))


# the reference: tight tolerances, and te steps enough to reach them (the default -max_inner_steps
# 20000 left the strips' first load step unbalanced)
REF_OPTS = ["-predict", "linear", "-balance_tol", "1e-8", "-speed_tol", "1e-8", "-max_inner_steps", "400000"]


def reference(scene):
    """the reference's curve rows; a reference that did not balance every load step stops the script"""
    rows, s = run(scene, strip + REF_OPTS)
    if not s.get("converged"):
        bad = [r["load_step"] for r in rows if r.get("balanced") not in ("1", "true")]
        sys.exit("bench_speedups: the reference of %s (%s) did not balance %s: no reference to measure errors against, no table" % (
            scene, " ".join(strip + REF_OPTS),
            "load step%s %s of %d" % ("s" if len(bad) > 1 else "", ", ".join(bad[:5]) + (", ..." if len(bad) > 5 else ""), len(rows))
            if bad else "every load step"))
    return rows


def balanced(s, early_exit="1"):
    """the balanced column: summary.json's converged; a fixed N te steps per load step (no early exit)
    balances nothing by design"""
    return "fixed N" if early_exit == "0" else str(bool(s.get("converged"))).lower()


def error_pct(rows, ref):
    peak = max(abs(float(r["force_N"])) for r in ref)
    return 100 * max(abs(float(a["force_N"]) - float(b["force_N"])) for a, b in zip(rows, ref)) / peak


def table(title, header, lines):
    print("\n" + title)
    w = [max(len(str(x)) for x in col) for col in zip(header, *lines)]
    for line in [header] + lines:
        print("  ".join(str(x).rjust(n) for x, n in zip(line, w)))
    sys.stdout.flush()


strip = ["-width_mm", "2"]


def table1():
    scenes = ["strip_warp.yaml", "strip_weft.yaml"]
    for scene in scenes:
        ref = reference(scene)
        # plain multi-sampling: smallest fixed N that reaches 1 % of the peak force
        sweep = [2000, 4000, 8000, 16000] if QUICK else [1000, 2000, 4000, 8000, 16000, 32000]
        lines, n_plain = [], None
        for n in sweep:
            rows, s = run(scene, strip + ["-predict", "none", "-early_exit", "0", "-front", "0", "-max_inner_steps", str(n)])
            e = error_pct(rows, ref)
            lines.append([n, "%.2f" % s["wall_s"], s["te_steps"], s["point_updates"], "%.3f" % e, balanced(s, "0")])
            if e <= 1.0 and n_plain is None:
                n_plain = n
                break
        table("%s: plain multi-sampling (no prediction, no early exit), error vs fixed N (balanced: fixed N, N te steps per load step whatever the balance)" % scene,
              ["N", "wall_s", "te_steps", "point_updates", "err_%peak", "balanced"], lines)
        if n_plain is None:
            n_plain = sweep[-1]
            print("plain multi-sampling did not reach 1 %% with N <= %d; using N = %d" % (n_plain, n_plain))
        lines = []
        base_wall = None
        configs = list(itertools.product(["none", "linear", "extrapolate"], ["0", "1"], ["0", "1"], ["0", "1e-4"]))
        for predict, early, front, sleep in configs:
            if early == "0" and sleep != "0":
                continue  # sleeping needs the balance test's thresholds: only with early exit
            opts = strip + ["-predict", predict, "-early_exit", early, "-front", front, "-sleep_tol", sleep, "-max_inner_steps", str(n_plain if early == "0" else 50000)]
            rows, s = run(scene, opts)
            e = error_pct(rows, ref)
            if base_wall is None:
                base_wall = s["wall_s"]
            nmax = max(int(r["inner_steps"]) for r in rows)
            lines.append(["predict=%s early_exit=%s front=%s sleep=%s" % (predict, early, front, sleep), "%.2f" % s["wall_s"], "%.1f" % (base_wall / s["wall_s"]), s["te_steps"], nmax, s["point_updates"], "%.3f" % e,
                          balanced(s, early)])
        table("%s (5 yarns, 50 load steps): every combination; plain multi-sampling N = %d; speed-up vs the first row; "
              "balanced: every load step (false: some stopped at the te steps allowed), fixed N without early exit" % (scene, n_plain),
              ["configuration", "wall_s", "speedup", "te_steps", "max_N'", "point_updates", "err_%peak", "balanced"], lines)



def table2():
    # Table 2: the trade for early exit without prediction
    scene = "strip_warp.yaml"
    pts, lines = [], []
    ref = reference(scene)
    for tol in (["1e-2", "1e-3", "1e-4"] if QUICK else ["1e-1", "1e-2", "1e-3", "1e-4", "1e-5"]):
        for safety in ["0.5", "0.9"]:
            speed_tol = "%g" % (100e-3 / 60 * float(tol) / 1e-3)  # the test speed at tol 1e-3, scaled with tol
            rows, s = run(scene, strip + ["-predict", "none", "-balance_tol", tol, "-speed_tol", speed_tol, "-te_safety", safety, "-max_inner_steps", "100000"])
            e = error_pct(rows, ref)
            lines.append([tol, safety, "%.2f" % s["wall_s"], s["te_steps"], max(int(r["inner_steps"]) for r in rows), "%.4f" % e, balanced(s)])
            pts.append((float(tol), float(safety), s["wall_s"], e))
    table("strip_warp (5 yarns): early exit without prediction, balance tolerance x te_safety; balanced: every load step "
          "(false: some stopped at the 100000 te steps allowed)", ["balance_tol", "te_safety", "wall_s", "te_steps", "max_N'", "err_%peak", "balanced"], lines)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for safety, marker in (("0.5", "s"), ("0.9", "o")):
            p = sorted((t, w, e) for t, sf, w, e in pts if sf == float(safety))
            ax.loglog([w for _, w, _ in p], [max(e, 1e-6) for _, _, e in p], marker=marker, label="te_safety %s" % safety)
            for t, w, e in p:
                ax.annotate("%g" % t, (w, max(e, 1e-6)), fontsize=7)
        ax.axhline(1.0, color="grey", lw=0.5)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("largest force error (% of peak)")
        ax.set_title("Strip test, early exit: balance tolerance (labels) vs time")
        ax.legend()
        fig.tight_layout()
        png = os.path.join(OUT, "speedups_trade.png")
        try:
            fig.savefig(png, dpi=120)
        except OSError as e:
            sys.exit("bench_speedups: %s: %s" % (png, e.strerror))
        print("wrote %s" % png)
    except ImportError:
        print("matplotlib not available: no PNG")



# Table 3: a local load on a large fabric
def displacements(binfile, nx):
    """|u| of every crossing from a -positions_out file (PETSc binary, natural order)"""
    data = open(binfile, "rb").read()
    n = struct.unpack(">i", data[4:8])[0]
    x = struct.unpack(">%dd" % n, data[8:8 + 8 * n])
    a = 1 / 2400.0  # local_2000: 24 threads/cm both ways
    u = []
    for k in range(n // 3):
        i, j = k % nx, k // nx
        u.append((x[3 * k] - i * a, x[3 * k + 1] - j * a, x[3 * k + 2]))
    return u


def table3():
    lines, ref = [], None
    steps = "100" if QUICK else "400"
    for name, opts in (("all points", ["-front", "0"]), ("front", ["-front", "1"]), ("front + sleep 1e-6", ["-front", "1", "-sleep_tol", "1e-6"]), ("front + sleep 1e-4", ["-front", "1", "-sleep_tol", "1e-4"])):
        binf = os.path.join(WORK, "local_%d.bin" % len(lines))
        rows, s = run("local_2000.yaml", opts + ["-max_inner_steps", steps, "-positions_out", binf])
        u = displacements(binf, 2000)
        mag = [(a * a + b * b + c * c) ** 0.5 for a, b, c in u]
        m = max(mag)
        if ref is None:
            ref, mref = u, m
        err = max(max(abs(p - q) for p, q in zip(a, b)) for a, b in zip(u, ref)) / mref
        moved3 = sum(1 for d in mag if d > 1e-3 * m) / len(mag)
        moved6 = sum(1 for d in mag if d > 1e-6 * m) / len(mag)
        lines.append([name, "%.2f" % s["wall_s"], s["te_steps"], s["point_updates"], "%.5f" % (s["point_updates"] / (int(steps) * 4e6)), "%.5f" % moved3, "%.5f" % moved6, "%.1e" % err])
    table("local_2000 (point load at the centre, %s te steps): fraction of the point updates vs fraction of the fabric that moves (|u| above 1e-3 / 1e-6 of the largest); position error vs all points, relative to the largest |u|" % steps,
          ["configuration", "wall_s", "te_steps", "point_updates", "updates/(steps*points)", "moved>1e-3", "moved>1e-6", "max_err"], lines)

# results/bench, for Table 2's PNG: a file there was a FileExistsError traceback (and the temporary
# directory, made before, was left behind); checked before anything is made
if "2" in TABLES:
    try:
        os.makedirs(OUT, exist_ok=True)
    except OSError as e:
        sys.exit("bench_speedups: %s: %s (Table 2 writes its PNG there)" % (OUT, "not a directory" if os.path.exists(OUT) else e.strerror))
def _stop(signum, frame):  # SIGTERM (kill, a batch system, ctest's timeout) stops the script as Ctrl-C does
    raise KeyboardInterrupt


signal.signal(signal.SIGTERM, _stop)
interrupted = False
try:
    WORK = tempfile.mkdtemp(prefix="bench_speedups_")
    if "1" in TABLES:
        table1()
    if "2" in TABLES:
        table2()
    if "3" in TABLES:
        table3()
except KeyboardInterrupt:  # the current run is stopped (run); no more tables
    signal.signal(signal.SIGINT, signal.SIG_IGN); signal.signal(signal.SIGTERM, signal.SIG_IGN)
    interrupted = True
finally:
    if WORK:
        shutil.rmtree(WORK, ignore_errors=True)
if interrupted:
    sys.stdout.flush()
    print("bench_speedups: interrupted", file=sys.stderr)
    sys.exit(130)


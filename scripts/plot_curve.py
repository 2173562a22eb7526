"""plot_curve.py - force vs elongation (or travel) of one or more runs, as a PNG.

    /usr/bin/python3 scripts/plot_curve.py RUN/curve.csv [RUN2/curve.csv ...] [-o curve.png]
                     [--labels A,B] [--measured measured.csv] [--title TEXT]

Each curve.csv is one line (elongation_pct, force_N; a pushing run's travel_mm, force_N),
labelled with its run directory's name (or --labels). Where the run's summary.json (next to its
curve.csv) reports a maximum force and a rupture, or a maximum above every row of the curve (a
located break's, between two load steps), the maximum is marked and the legend says it. --measured
overlays a measured curve: a CSV whose first two columns are the curves' x (elongation %, or travel
mm) and force (N), with or without a header line; it is drawn as points. Load steps that did not
balance (curve.csv's balanced column 0) are not marked: check that column. Default output:
curve.png next to the first curve.csv; -o DIR writes DIR/curve.png. Prints the file it wrote.
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_run(path):
    """x values, forces and the x column's name: elongation_pct (jaw tests) or travel_mm"""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows, names = list(reader), reader.fieldnames or []
    except (OSError, UnicodeDecodeError) as e:
        sys.exit(f"plot_curve.py: {path}: {e.strerror if isinstance(e, OSError) else e}")
    if "drop_mm" in names:
        sys.exit(f"plot_curve.py: {path}: a drape run's curve: its response is drop_mm, it has no force to plot")
    col = "elongation_pct" if "elongation_pct" in names else "travel_mm"
    if col not in names or "force_N" not in names:
        sys.exit(f"plot_curve.py: {path}: not a fabric curve.csv (expected the columns elongation_pct or travel_mm, and force_N)")
    if not rows:
        sys.exit(f"plot_curve.py: {path}: no load step in it (the run ended before its first load step)")
    # the curve starts at rest: 0, 0 N
    try:
        return [0.0] + [float(r[col]) for r in rows], [0.0] + [float(r["force_N"]) for r in rows], col
    except (TypeError, ValueError):
        sys.exit(f"plot_curve.py: {path}: a row whose {col} or force_N is not a number")


def read_maximum(path, forces):
    """(x, force, text) of the run's maximum force from summary.json next to curve.csv, if it ruptured or the
    maximum is none of the curve's forces; else None"""
    summary = os.path.join(os.path.dirname(os.path.abspath(path)), "summary.json")
    try:
        s = json.load(open(summary))
    except (OSError, ValueError):
        return None
    x = s.get("elongation_at_max_force_pct", s.get("travel_at_max_force_mm"))
    if not isinstance(s.get("max_force_N"), (int, float)) or not isinstance(x, (int, float)):
        return None
    if not s.get("rupture") and s["max_force_N"] <= max(forces):
        return None
    unit = "%" if "elongation_at_max_force_pct" in s else "mm"
    return x, s["max_force_N"], f"maximum {s['max_force_N']:.4g} N at {x:.4g} {unit}"


def read_measured(path):
    x, y = [], []
    try:
        with open(path, newline="") as f:
            for n, row in enumerate(csv.reader(f), 1):
                if not row or row[0].lstrip().startswith("#"):
                    continue
                if n == 1 and row[0].strip() == "load_step":  # its columns 1 and 2 are load_step and time_s
                    sys.exit(f"plot_curve.py: --measured {path}: a fabric curve.csv, not a measured curve "
                             "(x, force N): give it as a curve, before the options")
                try:
                    xy = float(row[0]), float(row[1])
                except (ValueError, IndexError):
                    if n == 1 or not x:  # a header line
                        continue
                    sys.exit(f"plot_curve.py: --measured {path} line {n}: expected two numbers (the curves' x, force N), got {row}")
                if not all(math.isfinite(v) for v in xy):  # nan, inf: no point to plot (it was left out without a word)
                    sys.exit(f"plot_curve.py: --measured {path} line {n}: expected two finite numbers (the curves' x, force N), got {row}")
                x.append(xy[0])
                y.append(xy[1])
    except (OSError, UnicodeDecodeError) as e:
        sys.exit(f"plot_curve.py: --measured {path}: {e.strerror if isinstance(e, OSError) else e}")
    if not x:
        sys.exit(f"plot_curve.py: --measured {path}: no data")
    return x, y


def main():
    p = argparse.ArgumentParser(description="Force vs elongation (or travel) from fabric curve.csv files, as a PNG.")
    p.add_argument("curves", nargs="+", help="curve.csv files of fabric runs")
    p.add_argument("-o", "--out", help="PNG file (default: curve.png next to the first curve.csv)")
    p.add_argument("--labels", help="comma-separated legend labels, one per curve.csv")
    p.add_argument("--measured", help="measured curve, CSV: the curves' x (elongation %%, or travel mm), force (N)")
    p.add_argument("--measured_label", default="measured", help="legend label of the measured curve")
    p.add_argument("--title", help="title (default: force vs elongation, or force vs travel, as the curves' x)")
    a = p.parse_args()
    labels = a.labels.split(",") if a.labels else [os.path.basename(os.path.dirname(os.path.abspath(c))) for c in a.curves]
    if len(labels) != len(a.curves):
        sys.exit(f"plot_curve.py: --labels gives {len(labels)} labels for {len(a.curves)} curves")
    fig, ax = plt.subplots(figsize=(8, 5.5), dpi=120)
    if a.out and os.path.isdir(a.out):  # it wrote DIR.png beside the directory (DIR.v2: "unknown image format")
        a.out = os.path.join(a.out, "curve.png")
    ext = os.path.splitext(a.out or "")[1][1:].lower()
    if ext and ext not in fig.canvas.get_supported_filetypes():
        p.error(f"argument -o/--out: {a.out}: unknown image format '.{ext}' (png, pdf, svg, ...)")
    runs = [read_run(path) for path in a.curves]
    cols = {run[2] for run in runs}
    if len(cols) > 1:
        sys.exit(f"plot_curve.py: the curves mix {' and '.join(sorted(cols))} (jaw tests against the others): plot them apart")
    col = cols.pop()
    for path, label, (x, y, _) in zip(a.curves, labels, runs):
        line = ax.plot(x, y, "-", marker=".", label=label)[0]
        peak = read_maximum(path, y)
        if peak:
            ax.plot([peak[0]], [peak[1]], "*", ms=12, color=line.get_color(), label=f"{label}: {peak[2]}")
    if a.measured:
        x, y = read_measured(a.measured)
        ax.plot(x, y, "o", mfc="none", color="k", label=a.measured_label)
    ax.set_xlabel("elongation (%)" if col == "elongation_pct" else "travel (mm)")
    ax.set_ylabel("force (N)")
    ax.set_title(a.title if a.title is not None else
                 "Force vs elongation" if col == "elongation_pct" else "Force vs travel")
    ax.grid(True, alpha=0.3)
    ax.legend()
    out = a.out or os.path.join(os.path.dirname(os.path.abspath(a.curves[0])), "curve.png")
    if not os.path.splitext(out)[1][1:]:  # matplotlib adds .png to a name without one: print the file it writes
        out = out.rstrip(".") + "." + plt.rcParams["savefig.format"]
    fig.tight_layout()
    try:
        fig.savefig(out)
    except (OSError, ValueError) as e:  # a folder that cannot be written, a format matplotlib has not
        sys.exit(f"plot_curve.py: -o {out}: {e.strerror if isinstance(e, OSError) else e}")
    print(out)


if __name__ == "__main__":
    main()

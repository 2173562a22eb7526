"""plot_curve.py - force vs elongation of one or more runs, as a PNG.

    /usr/bin/python3 scripts/plot_curve.py RUN/curve.csv [RUN2/curve.csv ...] [-o curve.png]
                     [--labels A,B] [--measured measured.csv] [--title TEXT]

Each curve.csv is one line (elongation_pct, force_N), labelled with its run directory's name
(or --labels). --measured overlays a measured curve: a CSV whose first two columns are
elongation (%) and force (N), with or without a header line; it is drawn as points. Load steps
that did not balance (curve.csv residual above -balance_tol) are not marked: check the residual
column. Default output: curve.png next to the first curve.csv. Prints the file it wrote.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_run(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "elongation_pct" not in rows[0] or "force_N" not in rows[0]:
        sys.exit(f"plot_curve.py: {path}: not a fabric curve.csv (expected the columns elongation_pct and force_N)")
    # the curve starts at rest: 0 % elongation, 0 N
    return [0.0] + [float(r["elongation_pct"]) for r in rows], [0.0] + [float(r["force_N"]) for r in rows]


def read_measured(path):
    x, y = [], []
    with open(path, newline="") as f:
        for n, row in enumerate(csv.reader(f), 1):
            if not row or row[0].lstrip().startswith("#"):
                continue
            try:
                x.append(float(row[0]))
                y.append(float(row[1]))
            except (ValueError, IndexError):
                if n == 1 or not x:  # a header line
                    continue
                sys.exit(f"plot_curve.py: --measured {path} line {n}: expected two numbers (elongation %, force N), got {row}")
    if not x:
        sys.exit(f"plot_curve.py: --measured {path}: no data")
    return x, y


def main():
    p = argparse.ArgumentParser(description="Force vs elongation from fabric curve.csv files, as a PNG.")
    p.add_argument("curves", nargs="+", help="curve.csv files of fabric runs")
    p.add_argument("-o", "--out", help="PNG file (default: curve.png next to the first curve.csv)")
    p.add_argument("--labels", help="comma-separated legend labels, one per curve.csv")
    p.add_argument("--measured", help="measured curve, CSV: elongation (%%), force (N)")
    p.add_argument("--measured_label", default="measured", help="legend label of the measured curve")
    p.add_argument("--title", default="Strip tensile test: force vs elongation")
    a = p.parse_args()
    labels = a.labels.split(",") if a.labels else [os.path.basename(os.path.dirname(os.path.abspath(c))) for c in a.curves]
    if len(labels) != len(a.curves):
        sys.exit(f"plot_curve.py: --labels gives {len(labels)} labels for {len(a.curves)} curves")
    fig, ax = plt.subplots(figsize=(8, 5.5), dpi=120)
    for path, label in zip(a.curves, labels):
        x, y = read_run(path)
        ax.plot(x, y, "-", marker=".", label=label)
    if a.measured:
        x, y = read_measured(a.measured)
        ax.plot(x, y, "o", mfc="none", color="k", label=a.measured_label)
    ax.set_xlabel("elongation (%)")
    ax.set_ylabel("force (N)")
    ax.set_title(a.title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    out = a.out or os.path.join(os.path.dirname(os.path.abspath(a.curves[0])), "curve.png")
    fig.tight_layout()
    fig.savefig(out)
    print(out)


if __name__ == "__main__":
    main()

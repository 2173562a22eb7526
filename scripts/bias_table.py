"""bias_table.py - a bias extension run against the kinematic formula (MODEL.md 11).

    /usr/bin/python3 scripts/bias_table.py RUN_DIR [--markdown]

Reads RUN_DIR/curve.csv and RUN_DIR/summary.json (gauge_mm and width_mm: the specimen as the
grid has it, its outline on the grid diagonals) and prints, per load step: the jaw travel d,
the pin-jointed-net formula gamma = 90 - 2 acos((D + d)/(sqrt(2) D)) degrees, D = gauge - width
("-" past d = (sqrt(2) - 1) D, where it reaches 90 degrees), the central zone's measured shear
angle, their difference, the force and the te steps of the load step (N', with a * if the load step
did not balance); then whether every load step balanced (curve.csv's balanced column) and, if the
specimen ruptured (summary.json "rupture"), where, and its maximum force: the load step of a rupture
is a tear, not a sheared specimen, so it gets no difference from the formula and is not counted as
a load step that did not balance. A run that stopped on an error
(summary.json "error") gets its table up to where it stopped, then the error on stderr and exit
status 1.
"""
import argparse
import csv
import json
import math
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="output directory of a -test bias run")
    ap.add_argument("--markdown", action="store_true", help="a Markdown table")
    a = ap.parse_args()
    try:
        summary = json.load(open(os.path.join(a.run, "summary.json")))
        with open(os.path.join(a.run, "curve.csv"), newline="") as f:
            reader = csv.DictReader(f)
            rows, names = list(reader), reader.fieldnames or []
    except (OSError, ValueError) as e:
        sys.exit(f"bias_table.py: {a.run}: {e}")
    if "center_shear_deg" not in names:
        sys.exit(f"bias_table.py: {a.run}/curve.csv: not a bias run (no center_shear_deg column)")
    if not rows:  # stopped before its first load step ended: summary.json says why
        why = f": {summary['error']}" if summary.get("error") else ""
        sys.exit(f"bias_table.py: {a.run}/curve.csv: no load step (the run stopped before its first){why}")
    for k, r in enumerate(rows, start=2):  # a row cut short (a run stopped while writing it) or not numbers
        try:
            [float(r[c]) for c in ("load_step", "travel_mm", "center_shear_deg", "force_N")]
        except (TypeError, ValueError):
            sys.exit(f"bias_table.py: {a.run}/curve.csv: line {k} is not a whole row of numbers "
                     f"(a run stopped while writing it?): {','.join(v for v in r.values() if isinstance(v, str))}")
    D = summary["gauge_mm"] - summary["width_mm"]
    head = ["travel_mm", "formula_deg", "centre_deg", "diff_deg", "force_N", "N'"]
    if a.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---:|" * len(head))
    else:
        print(" ".join(f"{h:>11}" for h in head))
    rupture = summary.get("rupture") or {}
    torn_row = [int(float(r["load_step"])) == rupture.get("load_step") for r in rows]  # the rupture's: its tear
    for r, torn in zip(rows, torn_row):
        d, centre = float(r["travel_mm"]), float(r["center_shear_deg"])
        c = (D + d) / (math.sqrt(2) * D)
        formula = 90 - 2 * math.degrees(math.acos(c)) if c <= 1 else None
        cells = [f"{d:.2f}", f"{formula:.2f}" if formula is not None else "-", f"{centre:.2f}",
                 f"{centre - formula:+.2f}" if formula is not None and not torn else "-", f"{float(r['force_N']):.4g}",
                 r["inner_steps"] + ("" if r.get("balanced", "1") == "1" else "*")]
        print("| " + " | ".join(cells) + " |" if a.markdown else " ".join(f"{x:>11}" for x in cells))
    if summary.get("error"):  # the table is the run's first load steps only
        sys.exit(f"bias_table.py: {a.run}: the run stopped after {len(rows)} load steps: {summary['error']}")
    balanced = all(r.get("balanced", "1") == "1" for r, torn in zip(rows, torn_row) if not torn)
    print(f"every load step{' before the rupture' if rupture else ''} balanced: {'yes' if balanced else 'NO (*)'}; "
          f"D = {D:.3f} mm")
    if rupture:
        print(f"ruptured in load step {rupture.get('load_step')}, at {rupture.get('elongation_pct', 0):.4g} % elongation "
              f"(its row: the tear's end); maximum force {summary.get('max_force_N', 0):.4g} N at "
              f"{summary.get('elongation_at_max_force_pct', 0):.4g} %")


if __name__ == "__main__":
    main()

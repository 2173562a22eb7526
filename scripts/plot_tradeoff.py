#!/usr/bin/python3
"""Error against wall time of the explicit path's knobs, from a table of scripts/tradeoff.sh.
   /usr/bin/python3 scripts/plot_tradeoff.py table.csv -o figure.png [--title TEXT]"""
import argparse, csv, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

ap = argparse.ArgumentParser(description=__doc__)
ap.add_argument("table")
ap.add_argument("-o", "--output", required=True)
ap.add_argument("--title", default="")
a = ap.parse_args()
try:
    with open(a.table, newline="") as f:
        rows = list(csv.DictReader(f))
except (OSError, UnicodeDecodeError) as e:
    sys.exit(f"plot_tradeoff.py: {a.table}: {e.strerror if isinstance(e, OSError) else e}")
# the error drawn: the force's (pushing, bias) or the drape coefficient's (drape)
col = next((c for c in ("force_err_pct", "dc_err_pts") if rows and c in rows[0]), None)
if col is None:
    sys.exit(f"plot_tradeoff.py: {a.table}: not a table of scripts/tradeoff.sh")
ylabel = {"force_err_pct": "largest force error against the reference [%]",
          "dc_err_pts": "drape coefficient error against the reference [points of %]"}[col]
fig, ax = plt.subplots(figsize=(6.4, 4.4))
floor = 1e-6  # the reference's own level; errors below it are drawn at it
for knob in dict.fromkeys(r["knob"] for r in rows if r["knob"] != "reference"):
    pts = [r for r in rows if r["knob"] == knob and r["wall_s"] != "-"]
    if not pts:  # stopped, refused or out of time: in the table only
        continue
    ax.scatter([float(r["wall_s"]) for r in pts], [max(float(r[col]), floor) for r in pts],
               label=knob, marker="o" if knob != "base" else "*", s=60 if knob == "base" else 30)
    for r in pts:
        if r["value"] != "-":
            ax.annotate(r["value"], (float(r["wall_s"]), max(float(r[col]), floor)), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
ref = [r for r in rows if r["knob"] == "reference" and r["wall_s"] != "-"]
if ref:
    ax.axvline(float(ref[0]["wall_s"]), color="gray", ls="--", lw=1, label=f"{ref[0]['value']} (reference)")
ax.set_xscale("log"); ax.set_yscale("log")
ax.set_xlabel("wall time on 2 ranks [s]"); ax.set_ylabel(ylabel)
ax.set_title(a.title, fontsize=10); ax.grid(True, which="both", lw=0.3); ax.legend(fontsize=7)
fig.tight_layout()
try:
    fig.savefig(a.output, dpi=110)
except (OSError, ValueError) as e:  # a folder that cannot be written, a format matplotlib has not
    sys.exit(f"plot_tradeoff.py: -o {a.output}: {e.strerror if isinstance(e, OSError) else e}")

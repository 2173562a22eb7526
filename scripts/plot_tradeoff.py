#!/usr/bin/python3
"""Error against wall time of the explicit path's knobs, from a table of scripts/tradeoff.sh.
   /usr/bin/python3 scripts/plot_tradeoff.py table.csv -o figure.png [--title TEXT]
-o DIR (an existing directory) writes DIR/tradeoff_TABLE.png (bias.csv: DIR/tradeoff_bias.png); a
name without an extension gets .png. Prints the file it wrote."""
import argparse, csv, math, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("table")
ap.add_argument("-o", "--output", required=True)
ap.add_argument("--title", default="")
a = ap.parse_args()


def fail(msg):
    sys.exit(f"plot_tradeoff.py: {msg}")


try:
    with open(a.table, newline="") as f:
        reader = csv.DictReader(f)
        names = reader.fieldnames or []
        # each row with its line in the file (the header is line 1; a quoted field never holds a line break here)
        rows = [dict(r, _line=reader.line_num) for r in reader]
except (OSError, UnicodeDecodeError, csv.Error) as e:
    fail(f"{a.table}: {e.strerror if isinstance(e, OSError) else e}")
# the error drawn: the force's (pushing, bias) or the drape coefficient's (drape)
col = next((c for c in ("force_err_pct", "dc_err_pts") if c in names), None)
if col is None:
    fail(f"{a.table}: not a table of scripts/tradeoff.sh (no force_err_pct or dc_err_pts column)")
missing = [c for c in ("knob", "value", "wall_s") if c not in names]
if missing:  # a KeyError traceback
    fail(f"{a.table}: no {' or '.join(missing)} column (not a table of scripts/tradeoff.sh)")


def number(r, c, positive=False):
    """a row's number: a clear message naming the file, the line and the column if it is not one"""
    v = r.get(c)
    try:
        x = float(v)
    except (TypeError, ValueError):
        x = math.nan
    if not math.isfinite(x) or x < 0 or (positive and x == 0):
        what = "missing (a row cut short)" if v is None else f"'{v}': not a number" + (" above 0" if positive else " of 0 or more")
        fail(f"{a.table} line {r['_line']} (knob {r['knob']}): {c} {what}")
    return x


# a row that ran has a wall time and an error (rows that stopped, were refused or ran out of time
# have '-' in both, and are in the table only)
timed = [r for r in rows if r["wall_s"] != "-"]
pts = [(r, number(r, "wall_s", positive=True), number(r, col)) for r in timed]
if not any(r["knob"] != "reference" for r, _, _ in pts):  # an empty plot, exit 0
    fail(f"{a.table}: no row but the reference ran (every one stopped, was refused or ran out of time: wall_s '-'): nothing to plot")
out = a.output
if os.path.isdir(out):  # it wrote DIR.png beside the directory
    out = os.path.join(out, "tradeoff_" + os.path.splitext(os.path.basename(a.table))[0] + ".png")
elif not os.path.splitext(out)[1][1:]:  # matplotlib adds .png to a name without one: say the file it writes
    out = out.rstrip(".") + "." + plt.rcParams["savefig.format"]
ylabel = {"force_err_pct": "largest force error against the reference [%]",
          "dc_err_pts": "drape coefficient error against the reference [points of %]"}[col]
fig, ax = plt.subplots(figsize=(6.4, 4.4))
floor = 1e-6  # the reference's own level; errors below it are drawn at it
for knob in dict.fromkeys(r["knob"] for r, _, _ in pts if r["knob"] != "reference"):
    kp = [(r, w, max(e, floor)) for r, w, e in pts if r["knob"] == knob]
    ax.scatter([w for _, w, _ in kp], [e for _, _, e in kp],
               label=knob, marker="o" if knob != "base" else "*", s=60 if knob == "base" else 30)
    for r, w, e in kp:
        if r["value"] not in ("-", None):
            ax.annotate(r["value"], (w, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
# a row whose run left a load step unbalanced: ringed in red (the table's balanced column says false)
loose = [(w, max(e, floor)) for r, w, e in pts if r["knob"] != "reference" and r.get("balanced") == "false"]
if loose:
    ax.scatter([w for w, _ in loose], [e for _, e in loose], s=160, facecolors="none", edgecolors="red", lw=1.2,
               label="a load step did not balance")
ref = [(r, w) for r, w, _ in pts if r["knob"] == "reference"]
if ref:
    ax.axvline(ref[0][1], color="gray", ls="--", lw=1, label=f"{ref[0][0]['value']} (reference)")
ax.set_xscale("log"); ax.set_yscale("log")
ax.set_xlabel("wall time on 2 ranks [s]"); ax.set_ylabel(ylabel)
ax.set_title(a.title, fontsize=10); ax.grid(True, which="both", lw=0.3); ax.legend(fontsize=7)
fig.tight_layout()
try:
    fig.savefig(out, dpi=110)
except (OSError, ValueError) as e:  # a folder that cannot be written, a format matplotlib has not
    fail(f"-o {out}: {e.strerror if isinstance(e, OSError) else e}")
print(out)

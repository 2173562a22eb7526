"""slack_census.py - a frame's yarn segments by chord strain: how many are slack, and how many lie near
the yarn law's kink at zero strain.

    /usr/bin/python3 scripts/slack_census.py RUN/fabric.h5 [--frame N]

Takes the segments between two crossings of the specimen (point_kind not -1) with at least one free
end (point_kind 0), along both yarn directions, and their chord strain e = L/L0 - 1: L from the
frame's positions, L0 from /grid/rest_positions (the model's rest chord). Prints one line: the
frame, the number of segments, how many are compressed (e < 0: the law's stiffness k_comp EA, the
yarn buckling) and how many have |e| below 1e-4, 1e-5, 1e-6 and 1e-7. The law's stiffness jumps at
e = 0 (docs/static.md, where it still fails: a drape at rest has many segments there). Default
frame: the last one written whole (a run stopped while writing a frame leaves it without its fields).
A broken segment (a run with yarn breaking) is counted as the others, with its chord strain:
fabric.h5 does not say which segments broke.
"""
import argparse
import os
import sys

import h5py
import numpy as np

THRESHOLDS = (1e-4, 1e-5, 1e-6, 1e-7)


def census(x, rest, kind):
    """the strains of the segments with a free end, both directions"""
    strains = []
    for axis in (0, 1):
        hi = tuple(slice(1, None) if a == axis else slice(None) for a in (0, 1))
        lo = tuple(slice(None, -1) if a == axis else slice(None) for a in (0, 1))
        length = np.linalg.norm(x[hi] - x[lo], axis=2)
        rest_length = np.linalg.norm(rest[hi] - rest[lo], axis=2)
        keep = ((kind[hi] == 0) | (kind[lo] == 0)) & (kind[hi] >= 0) & (kind[lo] >= 0)
        strains.append(length[keep] / rest_length[keep] - 1.0)
    return np.concatenate(strains)


def whole(frames, name, count):
    """frame `name` is counted by the root attribute "frames" and its group opens with its positions"""
    try:
        return name.isdigit() and int(name) < count and "positions" in frames[name]
    except (KeyError, OSError):  # a group that a run killed while writing it left unreadable
        return False


def main():
    p = argparse.ArgumentParser(description="A frame's yarn segments by chord strain (slack, near zero).")
    p.add_argument("h5", help="a run's fabric.h5")
    p.add_argument("--frame", type=int, help="the frame's number (default: the last one written whole)")
    a = p.parse_args()
    if not os.path.isfile(a.h5):
        what = "a directory" if os.path.isdir(a.h5) else "not a regular file" if os.path.exists(a.h5) else "no such file"
        sys.exit(f"slack_census.py: {a.h5}: {what}")
    try:
        f = h5py.File(a.h5, "r")
    except OSError as e:
        sys.exit(f"slack_census.py: {a.h5}: {'a truncated HDF5 file' if 'truncated' in str(e) else e.strerror or 'not an HDF5 file'}")
    with f:
        if not all(isinstance(f.get(n), t) for n, t in (("frames", h5py.Group), ("grid/rest_positions", h5py.Dataset),
                                                         ("grid/point_kind", h5py.Dataset))):
            sys.exit(f"slack_census.py: {a.h5}: not a fabric.h5 (expected /frames, /grid/rest_positions and /grid/point_kind)")
        # a frame is whole once the root attribute "frames" counts it (fabric writes it after the frame's fields)
        count = int(f.attrs.get("frames", 0))
        frames = sorted(int(n) for n in f["frames"] if whole(f["frames"], n, count))
        if not frames:
            sys.exit(f"slack_census.py: {a.h5}: no frame written whole in it")
        index = frames[-1] if a.frame is None else a.frame
        if index not in frames:
            sys.exit(f"slack_census.py: --frame {a.frame}: not in {a.h5} (its frames written whole: {frames[0]} to {frames[-1]})")
        try:
            x, rest, kind = f[f"frames/{index:06d}/positions"][:], f["grid/rest_positions"][:], f["grid/point_kind"][:]
        except (KeyError, OSError) as e:
            sys.exit(f"slack_census.py: {a.h5}: frame {index}: cannot be read ({e})")
    if x.ndim != 3 or x.shape != rest.shape or kind.shape != x.shape[:2] or x.shape[2] != 3:
        sys.exit(f"slack_census.py: {a.h5}: frame {index}: positions {x.shape}, rest positions {rest.shape} and point kinds "
                 f"{kind.shape} do not make one grid")
    e = census(x, rest, kind)
    bad = int(np.sum(~np.isfinite(e)))
    if bad:
        sys.exit(f"slack_census.py: {a.h5}: frame {index}: {bad} segments with a strain that is not a number (a run that diverged?)")
    near = ", ".join(f"|e| < {t:g}: {int(np.sum(np.abs(e) < t))}" for t in THRESHOLDS)
    print(f"frame {index}: {e.size} segments with a free end, {int(np.sum(e < 0))} compressed (e < 0); {near}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""check_pushing.py CURVE POSITIONS NX NY [--fourfold]: the pushing test's checks.

- force_N rises strictly with travel_mm (curve.csv of -test pushing);
- the final positions (-positions_out: PETSc binary, big-endian int32 class id, int32 n,
  n big-endian doubles, natural order: i fastest, 3 per crossing) keep the set-up's mirror
  symmetries x -> -x and y -> -y about the grid centre, and with --fourfold the diagonal one
  (x <-> y, warp and weft the same yarn and density), to 1e-6 relative: the largest
  difference between a crossing and its mirrored partner over the largest displacement.
"""
import csv
import sys

import numpy as np


def load(path, nx, ny):
    b = open(path, "rb").read()
    n = int(np.frombuffer(b[4:8], ">i4")[0])
    assert n == 3 * nx * ny, f"{path}: {n} values, expected 3 x {nx} x {ny}"
    return np.frombuffer(b[8:8 + 8 * n], ">f8").reshape(ny, nx, 3)


def main():
    curve, pos, nx, ny = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    fourfold = "--fourfold" in sys.argv
    fail = 0
    rows = list(csv.DictReader(open(curve)))
    travel = [float(r["travel_mm"]) for r in rows]
    force = [float(r["force_N"]) for r in rows]
    rising = all(b > a for a, b in zip(force, force[1:])) and force[0] > 0
    print(f"{'PASS' if rising else 'FAIL'} force rises with travel: " + ", ".join(f"{t:.2f} mm {f:.4g} N" for t, f in zip(travel, force)))
    fail += not rising

    x = load(pos, nx, ny)
    i = np.arange(nx)
    j = np.arange(ny)
    # rest positions and the grid centre, from the spacing of the file's untouched corner rows
    x0 = x[0, 0]
    c = 0.5 * (x[0, nx - 1, :2] + x[ny - 1, 0, :2])  # corner crossings lie outside the disc: at rest
    u = x.copy()
    ax = (x[0, nx - 1, 0] - x[0, 0, 0]) / (nx - 1)
    ay = (x[ny - 1, 0, 1] - x[0, 0, 1]) / (ny - 1)
    u[..., 0] -= i[None, :] * ax + x0[0]
    u[..., 1] -= j[:, None] * ay + x0[1]
    scale = np.abs(u).max()
    checks = [("mirror x -> -x", x[:, ::-1] * [-1, 1, 1] + [2 * c[0], 0, 0]),
              ("mirror y -> -y", x[::-1, :] * [1, -1, 1] + [0, 2 * c[1], 0])]
    if fourfold:
        assert nx == ny
        t = np.transpose(x, (1, 0, 2))[..., [1, 0, 2]]
        checks.append(("diagonal x <-> y", t))
    for what, m in checks:
        err = np.abs(x - m).max() / scale
        ok = err <= 1e-6
        print(f"{'PASS' if ok else 'FAIL'} {what}: largest difference / largest displacement = {err:.3e} (tolerance 1e-6; largest displacement {scale * 1e3:.4g} mm)")
        fail += not ok
    sys.exit(1 if fail else 0)


main()

"""check_paraview.py - ParaView's own XDMF readers open DIR/fabric.xmf as the time series that
DIR/fabric.h5 holds. Run with pvpython (Debian package python3-paraview):

    pvpython tests/check_paraview.py DIR FRAMES [te]

Asserts, for ParaView's XDMF reader (Xdmf2) and its Xdmf3 readers (S and T) alike:
  - the series has FRAMES time steps, at the times stored in fabric.h5, and the load-step frames
    are at the time_s of their load step in curve.csv (frame 0, the rest state, at 0); with
    "te" (a run with -output_te_every), a frame of load step k is at or after the time_s of k
    and before that of k + 1;
  - the grid is a structured nx x ny x 1 grid of 3-D points with every field;
  - for the first, a middle and the last frame, the points ParaView reads equal the HDF5
    positions, and its warp_tension, displacement and point_kind equal the HDF5 values (exactly).
Prints one PASS/FAIL line per check and exits non-zero if any failed.
"""
import csv
import os
import sys

import h5py
import numpy as np
from paraview import servermanager
from paraview.simple import XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT
from vtkmodules.util.numpy_support import vtk_to_numpy

FIELDS = ["velocities", "displacement", "warp_tension", "weft_tension", "shear_angle_deg", "point_kind"]
failures = 0


def check(ok, what):
    global failures
    print(("PASS " if ok else "FAIL ") + what)
    if not ok:
        failures += 1


def dataset(reader):
    data = servermanager.Fetch(reader)
    while data.IsA("vtkMultiBlockDataSet") or data.IsA("vtkPartitionedDataSetCollection") or data.IsA("vtkPartitionedDataSet"):
        data = data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data.GetPartition(0, 0) if data.IsA("vtkPartitionedDataSetCollection") else data.GetPartition(0)
    return data


def main():
    out, expected, te_frames = sys.argv[1], int(sys.argv[2]), len(sys.argv) > 3 and sys.argv[3] == "te"
    xmf = os.path.join(os.path.abspath(out), "fabric.xmf")  # the Xdmf3 readers need a directory in the name
    h5 = h5py.File(os.path.join(out, "fabric.h5"), "r")
    nx, ny = int(h5.attrs["nx"]), int(h5.attrs["ny"])
    names = sorted(h5["frames"].keys())
    check(int(h5.attrs["frames"]) == expected and len(names) == expected, f"fabric.h5 holds {len(names)} frames (attribute frames = {int(h5.attrs['frames'])}), expected {expected}")
    times = np.array([h5["frames"][n].attrs["time_s"] for n in names])
    steps = [int(h5["frames"][n].attrs["load_step"]) for n in names]
    check(bool(np.all(np.diff(times) > 0)), "frame times increase")

    with open(os.path.join(out, "curve.csv")) as f:
        time_s = {int(r["load_step"]): float(r["time_s"]) for r in csv.DictReader(f)}
    time_s[0] = 0.0
    # curve.csv keeps 9 significant digits
    tol = lambda t: 1e-8 * max(1.0, abs(t))
    if te_frames:
        last = max(time_s)
        time_s[last + 1] = float("inf")
        check(all(time_s[k] - tol(t) <= t < time_s[k + 1] - tol(t) for t, k in zip(times, steps)), f"te-step frame times are within their load steps ({len(times)} frames of {len(set(steps))} load steps)")
    else:
        check(all(abs(t - time_s[k]) <= tol(t) for t, k in zip(times, steps)), f"frame times = time_s of their load steps in curve.csv: {list(zip(steps, times))}")

    readers = (("XDMFReader (Xdmf2)", lambda: XDMFReader(FileNames=[xmf])), ("Xdmf3ReaderS", lambda: Xdmf3ReaderS(FileName=xmf)), ("Xdmf3ReaderT", lambda: Xdmf3ReaderT(FileName=xmf)))
    for label, make in readers:
        reader = make()
        tv = np.array(reader.TimestepValues if len(names) > 1 else [reader.TimestepValues]).ravel()
        check(len(tv) == expected, f"{label}: {len(tv)} time steps, expected {expected}")
        check(len(tv) == len(times) and bool(np.all(tv == times)), f"{label}: time steps equal the HDF5 frame times")
        for k in sorted({0, len(names) // 2, len(names) - 1}):
            reader.UpdatePipeline(float(times[k]))  # (simple.UpdatePipeline ignores time 0)
            data = dataset(reader)
            frame = h5["frames"][names[k]]
            dims = [0, 0, 0]
            if data.IsA("vtkStructuredGrid"):
                data.GetDimensions(dims)
            check(data.IsA("vtkStructuredGrid") and tuple(dims) == (nx, ny, 1), f"{label} frame {k}: a structured grid {dims} (expected ({nx}, {ny}, 1)) of type {data.GetClassName()}")
            pts = vtk_to_numpy(data.GetPoints().GetData())
            ref = frame["positions"][...].reshape(-1, 3)
            check(pts.shape == ref.shape and bool(np.array_equal(pts, ref)), f"{label} frame {k} (t = {times[k]:.9g} s): ParaView's {pts.shape[0]} points equal the HDF5 positions")
            pd = data.GetPointData()
            missing = [n for n in FIELDS if pd.GetArray(n) is None]
            check(not missing, f"{label} frame {k}: point fields {FIELDS} present" + (f" (missing {missing})" if missing else ""))
            if missing:
                continue
            for name, ref in (("warp_tension", frame["warp_tension"][...].ravel()), ("displacement", frame["displacement"][...].reshape(-1, 3)), ("point_kind", h5["grid/point_kind"][...].ravel())):
                got = vtk_to_numpy(pd.GetArray(name))
                check(got.shape == ref.shape and bool(np.array_equal(got, ref)), f"{label} frame {k}: {name} read by ParaView equals the HDF5 values (max |value| {np.abs(ref).max():.6g})")
    print(f"{failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

"""render.py - PNG images of frames of a fabric run, the fabric coloured by yarn tension.

    xvfb-run -a -s -noreset pvbatch scripts/render.py DIR [--frames 0,5,last | all] [--field warp_tension]
                                              [--out PREFIX] [--size 1600x900] [--range LO,HI]
                                              [--view angle|top|side] [--panel FILE.png]

DIR is a run's -output_dir (it holds fabric.xmf and fabric.h5). One image per frame,
the crossings outside the specimen's shape (point_kind -1) left out,
PREFIX_NNNNNN.png (default DIR/render/frame_NNNNNN.png), of the deformed fabric seen from above
at an angle, coloured by --field (any point field of fabric.xmf: warp_tension, weft_tension,
shear_angle_deg, ...) on one colour scale for all the chosen frames (its range over them, or
--range), with the load step and the test time written on the image. Prints the files it wrote.

--panel FILE.png also joins the chosen frames side by side into FILE.png, all seen with one
camera (fitted to the last chosen frame) so that the deformation can be compared: the paper's
figure 11 is three steps of the pushing test,

    xvfb-run -a -s -noreset pvbatch scripts/render.py results/pushing --frames 1,2,last --panel fig11.png
"""
import argparse
import math
import re
import os
import sys

from paraview.simple import (ColorBy, GetColorTransferFunction, GetScalarBar, Render, SaveScreenshot, Show, Text, Threshold, XDMFReader, CreateView)

TITLES = {
    "warp_tension": "warp yarn tension (N)",
    "weft_tension": "weft yarn tension (N)",
    "shear_angle_deg": "shear angle (degrees)",
    "point_kind": "point: 0 free, 1 clamped, 2 grip",
}


def parse():
    p = argparse.ArgumentParser(description="Render frames of DIR/fabric.xmf to PNG (run with xvfb-run -a -s -noreset pvbatch).")
    p.add_argument("dir", help="the run's -output_dir, holding fabric.xmf and fabric.h5")
    p.add_argument("--frames", default="last", help="comma-separated frame numbers, 'last', or 'all' (default: last)")
    p.add_argument("--field", default="warp_tension", help="point field to colour by (default: warp_tension)")
    p.add_argument("--out", default=None, help="file name prefix (default: DIR/render/frame)")
    p.add_argument("--size", default="1600x900", help="image size WxH in pixels (default: 1600x900)")
    p.add_argument("--view", default="angle", choices=["angle", "top", "side"], help="camera: above at an angle (default), straight from above, or from the side (along -y)")
    p.add_argument("--range", default=None, help="colour scale LO,HI (default: the field's range over the chosen frames)")
    p.add_argument("--panel", default=None, help="also join the chosen frames side by side into this PNG, seen with one camera")
    # "--range -5,5": argparse takes a value that starts with '-' for an option; join a number range to its flag
    argv = sys.argv[1:]
    for k in range(len(argv) - 1):
        if argv[k] == "--range" and re.fullmatch(r"-[0-9.eE+-]*,[-0-9.eE+]*", argv[k + 1]):
            argv[k:k + 2] = ["--range=" + argv[k + 1]]
            break
    a = p.parse_args(argv)
    if a.frames != "all" and not all(f.strip() == "last" or f.strip().isdigit() for f in a.frames.split(",")):
        p.error(f"argument --frames: {a.frames!r}: comma-separated frame numbers and 'last', or 'all'")
    size = a.size.lower().split("x")
    if len(size) != 2 or not all(v.strip().isdigit() and int(v) > 0 for v in size):
        p.error(f"argument --size: {a.size!r}: WxH in pixels, e.g. 1600x900")
    a.size = [int(v) for v in size]
    if a.range is not None:
        text = a.range
        try:
            a.range = [float(v) for v in text.split(",")]
        except ValueError:
            a.range = []
        if len(a.range) != 2 or not all(math.isfinite(v) for v in a.range):
            p.error(f"argument --range: {text!r}: LO,HI, two numbers")
        if a.range[0] >= a.range[1]:
            p.error(f"argument --range: {text!r}: LO must be below HI")
    return a


def main():
    a = parse()
    xmf = os.path.join(os.path.abspath(a.dir), "fabric.xmf")
    if not os.path.isfile(xmf):
        sys.exit(f"render.py: {xmf}: no such file (run fabric with -output_every K first)")
    h5 = os.path.join(os.path.abspath(a.dir), "fabric.h5")
    if not os.path.isfile(h5):
        sys.exit(f"render.py: {h5}: no such file (fabric.xmf describes the frames, fabric.h5 holds them)")
    for f in (xmf, h5):  # a run stopped before writing them: the reader's errors named --field
        if os.path.getsize(f) == 0:
            sys.exit(f"render.py: {f}: empty (the run that wrote it stopped before its first frame?)")
    with open(h5, "rb") as fh:
        if fh.read(8) != b"\x89HDF\r\n\x1a\n":
            sys.exit(f"render.py: {h5}: not an HDF5 file")
    reader = XDMFReader(FileNames=[xmf])
    reader.UpdatePipelineInformation()
    try:  # a property of the frames' times (one frame: a property of length 1)
        times = [float(t) for t in reader.TimestepValues]
    except TypeError:  # some ParaView versions give one time as a number
        times = [float(reader.TimestepValues)]
    times = times or [0.0]  # a file without times: its one grid
    n = len(times)
    if a.frames == "all":
        frames = list(range(n))
    else:
        frames = []
        for f in a.frames.split(","):
            k = n - 1 if f.strip() == "last" else int(f)
            if not 0 <= k < n:
                sys.exit(f"render.py: --frames {a.frames}: frame {k} does not exist ({xmf} has frames 0 to {n - 1})")
            frames.append(k)
    w, h = a.size
    prefix = a.out or os.path.join(os.path.abspath(a.dir), "render", "frame")
    make_folder("--out", prefix)
    if a.panel:
        make_folder("--panel", a.panel)

    names = [reader.PointData.GetArray(i).Name for i in range(len(reader.PointData))]
    if not names:
        sys.exit(f"render.py: {xmf} and {h5} give no field: damaged or cut short (a run stopped while writing them?)")
    if a.field not in names:
        sys.exit(f"render.py: --field {a.field}: not a field of {xmf} (it has {', '.join(names)})")
    def unreadable(k):
        return (f"render.py: frame {k} of {xmf}: {a.field} cannot be read from {h5} (a run killed while writing that "
                "frame?); choose others with --frames")

    if a.range:
        lo, hi = a.range
    else:
        lo, hi = float("inf"), float("-inf")
        for k in frames:
            reader.UpdatePipeline(times[k])
            arr = reader.PointData[a.field]
            if arr is None:  # its arrays past what the file holds: a run killed while writing it
                sys.exit(unreadable(k))
            r = arr.GetRange(-1 if arr.GetNumberOfComponents() > 1 else 0)  # a vector is coloured by its magnitude
            lo, hi = min(lo, r[0]), max(hi, r[1])
        if hi <= lo:
            hi = lo + 1e-12
    print(f"render.py: colour scale of {a.field}: {lo:.9g} to {hi:.9g}")

    view = CreateView("RenderView")
    view.ViewSize = [w, h]
    view.Background = [1, 1, 1]
    try:  # ParaView >= 5.10 takes the background from the colour palette unless told
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesVisibility = 1
    # crossings outside the specimen's shape (point_kind -1: disc, bias) are not drawn
    fabric = reader
    if "point_kind" in names:
        fabric = Threshold(Input=reader)
        fabric.Scalars = ["POINTS", "point_kind"]
        fabric.LowerThreshold = -0.5
        fabric.UpperThreshold = 1e9
        fabric.ThresholdMethod = "Between"
    shown = Show(fabric, view)
    shown.Representation = "Surface"
    ColorBy(shown, ("POINTS", a.field))
    lut = GetColorTransferFunction(a.field)
    lut.ApplyPreset("Turbo", True)
    lut.RescaleTransferFunction(lo, hi)
    lut.AutomaticRescaleRangeMode = "Never"
    bar = GetScalarBar(lut, view)
    bar.Title = TITLES.get(a.field, a.field)
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bar.Visibility = 1
    shown.SetScalarBarVisibility(view, True)

    label = Text()
    label_shown = Show(label, view)
    label_shown.Color = [0, 0, 0]
    label_shown.WindowLocation = "Upper Left Corner"

    # seen from above the fabric, at an angle: its x (warp) axis runs across the image; a panel
    # keeps one camera for all frames, fitted to the last (the most deformed)
    reader.UpdatePipeline(times[frames[-1] if a.panel else frames[0]])
    (x0, x1, y0, y1, z0, z1) = reader.GetDataInformation().GetBounds()
    cx, cy, cz = (x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2
    size = max(x1 - x0, y1 - y0, z1 - z0, 1e-9)
    view.CameraFocalPoint = [cx, cy, cz]
    if a.view == "top":  # the outline seen from above (the drape's shadow)
        view.CameraPosition = [cx, cy, cz + 2.0 * size]
        view.CameraViewUp = [0, 1, 0]
    elif a.view == "side":
        view.CameraPosition = [cx, cy - 2.0 * size, cz]
        view.CameraViewUp = [0, 0, 1]
    else:
        view.CameraPosition = [cx, cy - 0.9 * size, cz + 1.1 * size]
        view.CameraViewUp = [0, 0, 1]
    view.ResetCamera()
    if a.panel:
        view.ViewTime = times[frames[-1]]
        Render(view)
        view.ResetCamera()
        view.GetActiveCamera().Dolly(1.3)

    info = {}
    try:  # load step of each frame, from fabric.h5
        import h5py
        with h5py.File(h5, "r") as f:
            for i, name in enumerate(sorted(f["frames"].keys())):
                info[i] = int(f["frames"][name].attrs["load_step"])
    except Exception:
        pass
    written = []
    for k in frames:
        view.ViewTime = times[k]
        reader.UpdatePipeline(times[k])
        if reader.PointData[a.field] is None:  # with --range: the frames were not read before
            stop(unreadable(k))
        step = f"load step {info[k]}, " if k in info else ""
        label.Text = f"frame {k}: {step}t = {times[k]:.6g} s"
        if not a.panel:
            view.ResetCamera()
            view.GetActiveCamera().Dolly(1.3)  # ResetCamera fits the bounding sphere: fill more of the image
        Render(view)
        out = f"{prefix}_{k:06d}.png"
        try:  # an image that cannot be written: VTK logs why, SaveScreenshot still says it was written
            os.remove(out)
        except OSError:
            pass
        SaveScreenshot(out, view, ImageResolution=[w, h])
        if not os.path.isfile(out):
            stop(f"render.py: {out}: the image could not be written")
        written.append(out)
        print(out)
    if a.panel:
        join(written, a.panel)
        print(a.panel)


def make_folder(flag, path):
    """the folder of an output file, before the view exists (a file there: a traceback)"""
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        sys.exit(f"render.py: {flag} {path}: {folder}: {'not a directory' if os.path.exists(folder) else e.strerror}")


def stop(message):
    """exit 1 with the message once the view exists (sys.exit there: X's GLXBadContext error besides)"""
    print(message, file=sys.stderr, flush=True)
    sys.stdout.flush()
    os._exit(1)


def join(files, out):
    """the images side by side, left to right, in one PNG (VTK's image filters: in every pvbatch)"""
    from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
    from vtkmodules.vtkFiltersCore import vtkImageAppend

    append = vtkImageAppend()
    append.SetAppendAxis(0)
    readers = []
    for f in files:
        r = vtkPNGReader()
        r.SetFileName(f)
        r.Update()
        readers.append(r)
        append.AddInputConnection(r.GetOutputPort())
    writer = vtkPNGWriter()
    writer.SetFileName(out)
    writer.SetInputConnection(append.GetOutputPort())
    writer.Write()
    if writer.GetErrorCode():
        stop(f"render.py: --panel {out}: the image could not be written")


if __name__ == "__main__":
    main()

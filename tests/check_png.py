"""check_png.py - the images of scripts/render.py and scripts/plot_curve.py show something.

    /usr/bin/python3 tests/check_png.py render FIRST.png LAST.png WxH
    /usr/bin/python3 tests/check_png.py plot CURVE.png
    /usr/bin/python3 tests/check_png.py panel PANEL.png N WxH

render: both images are WxH; the fabric (pixels that are not the white background, in the
middle of the image, away from the text, axes and scalar bar) covers more than 3 % of it; its
colour moves to the red end of the scale between the two frames (the yarn tension rose: dark
blue-violet at rest, red at the end on the Turbo scale).
panel: render.py --panel of N frames: the image is N*W x H; in each of its N parts the fabric
covers more than 3 % of the middle; the high-tension colours (orange to red: R > 0.6, B < 0.3)
cover under 1 % of the first part's middle and over 5 % of the last's.
plot: the image has axes, lines and markers (more than 1 % of its pixels are coloured, more than
2 % are not white).
"""
import sys

import matplotlib.image as mpimg
import numpy as np

failures = 0


def check(ok, what):
    global failures
    print(("PASS " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


def load(path):
    img = mpimg.imread(path)[..., :3].astype(float)
    if img.max() > 1.0:
        img /= 255.0
    return img


def coloured(img):
    """pixels whose channels differ: not white, grey or black (text and axes are black)"""
    return (img.max(axis=2) - img.min(axis=2)) > 0.15


if sys.argv[1] == "render":
    first, last = load(sys.argv[2]), load(sys.argv[3])
    w, h = (int(v) for v in sys.argv[4].split("x"))
    for name, img in ((sys.argv[2], first), (sys.argv[3], last)):
        check(img.shape[:2] == (h, w), f"{name}: {img.shape[1]}x{img.shape[0]} pixels, expected {w}x{h}")
    # the middle of the image, away from the scalar bar (right) and the text (top)
    mid = lambda img: img[h // 5: 4 * h // 5, w // 10: 7 * w // 10]
    fa, fb = mid(first).min(axis=2) < 0.9, mid(last).min(axis=2) < 0.9
    check(fa.mean() > 0.03 and fb.mean() > 0.03, f"the fabric covers {100 * fa.mean():.1f} % and {100 * fb.mean():.1f} % of the middle of the images")
    if fa.any() and fb.any():
        ca, cb = mid(first)[fa].mean(axis=0), mid(last)[fb].mean(axis=0)
        check(cb[0] - cb[2] > ca[0] - ca[2] + 0.2, f"its colour moves to the red (high tension) end: mean RGB {np.round(ca, 2)} at the first frame, {np.round(cb, 2)} at the last")
elif sys.argv[1] == "panel":
    img, n = load(sys.argv[2]), int(sys.argv[3])
    w, h = (int(v) for v in sys.argv[4].split("x"))
    check(img.shape[:2] == (h, n * w), f"{sys.argv[2]}: {img.shape[1]}x{img.shape[0]} pixels, expected {n * w}x{h} ({n} frames side by side)")
    warm = []
    for q in range(n):
        part = img[h // 5: 4 * h // 5, q * w + w // 10: q * w + 7 * w // 10]
        fab = part.min(axis=2) < 0.9
        check(fab.mean() > 0.03, f"part {q + 1}: the fabric covers {100 * fab.mean():.1f} % of its middle")
        warm.append(((part[..., 0] > 0.6) & (part[..., 2] < 0.3)).mean())  # orange to red on Turbo
    check(warm[0] < 0.01 and warm[-1] > 0.05, f"the high-tension colours (orange to red) cover under 1 % of the first part's middle and over 5 % of the last's: {np.round(100 * np.array(warm), 1)} %")
else:
    img = load(sys.argv[2])
    nonwhite = (img.min(axis=2) < 0.9).mean()
    check(coloured(img).mean() > 0.01 and nonwhite > 0.02, f"{sys.argv[2]}: {img.shape[1]}x{img.shape[0]}, {100 * coloured(img).mean():.1f} % coloured, {100 * nonwhite:.1f} % not white")
print(f"{failures} failed")
sys.exit(1 if failures else 0)

#!/usr/bin/env python3
"""Where a method's error sits: for each final image `<label>_v<view>_<method>.exr` that
`smlt bench` wrote into OUT, against that folder's `reference_<label>_v<view>.exr`, the relMSE
(smlt's definition: mean over pixels and channels of d^2 / (ref^2 + 0.01)), the share of it
from the worst 1 % of pixels, and its split by the reference's luminance quartiles (darkest
first), as a Markdown table.

    python3 error_shares.py OUT [--methods pt,naive,path-naive]

A diagnosis, not a score: one repeat's image (the bench keeps the last repeat's)."""

import argparse
import glob
import os
import re

import numpy as np


def read_exr(path):
    import mitsuba as mi

    if not mi.variant():
        mi.set_variant("scalar_rgb")
    bitmap = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return np.array(bitmap)


def shares(image, reference):
    """relMSE, the worst 1 % of pixels' share of it, and each luminance quartile's share."""
    per_pixel = ((image - reference) ** 2 / (reference**2 + 0.01)).mean(axis=2).ravel()
    total = per_pixel.sum()
    worst = np.sort(per_pixel)[::-1][: max(1, per_pixel.size // 100)].sum()
    lum = (0.2126 * reference[..., 0] + 0.7152 * reference[..., 1] + 0.0722 * reference[..., 2]).ravel()
    order = np.argsort(lum, kind="stable")
    quartiles = [per_pixel[q].sum() / total for q in np.array_split(order, 4)]
    return per_pixel.mean(), worst / total, quartiles


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--methods", default=None, help="comma-separated (default: every final image found)")
    a = ap.parse_args()
    wanted = a.methods.split(",") if a.methods else None
    print("| view | method | relMSE | worst 1 % of pixels | darkest quartile | 2nd | 3rd | brightest |")
    print("|---|---|---|---|---|---|---|---|")
    for ref_path in sorted(glob.glob(os.path.join(a.out, "reference_*_v*.exr"))):
        m = re.match(r"reference_(.+)_v(\d+)\.exr$", os.path.basename(ref_path))
        label, view = m.group(1), m.group(2)
        reference = read_exr(ref_path)
        for path in sorted(glob.glob(os.path.join(a.out, f"{label}_v{view}_*.exr"))):
            method = os.path.basename(path)[len(f"{label}_v{view}_"):-4]
            if wanted and method not in wanted:
                continue
            rel, worst, q = shares(read_exr(path), reference)
            cells = " | ".join(f"{100 * x:.0f} %" for x in q)
            print(f"| {label} v{view} | {method} | {rel:.4f} | {100 * worst:.0f} % | {cells} |")


if __name__ == "__main__":
    main()

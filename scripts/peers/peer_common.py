"""What the peers share: PLY output, smlt's error definitions, the bench's time grid and its
results.csv format."""

import argparse
import math
import os

import numpy as np

HEADER = "scene,view,method,repeat,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr,nan_inf,b,b_rel_se"


def write_ply(path, tris, uv=None, normals=None):
    """Binary PLY of flat triangles (n, 3, 3), with texture coordinates uv (n, 3, 2) as the
    vertices' `u`, `v` where given (Mitsuba's `ply` reads them as they are, no flip) and shading
    normals (n, 3, 3) as the vertices' `nx`, `ny`, `nz` where given (what Mitsuba's `ply`
    interpolates when loaded with `face_normals` false). Each triangle has its own three
    vertices, so a corner's normal is the triangle's own: nothing is shared or averaged."""
    verts = tris.reshape(-1, 3).astype("<f4")
    if normals is not None:
        verts = np.concatenate([verts, normals.reshape(-1, 3).astype("<f4")], axis=1)
    if uv is not None:
        verts = np.concatenate([verts, uv.reshape(-1, 2).astype("<f4")], axis=1)
    faces = np.arange(len(tris) * 3, dtype="<i4").reshape(-1, 3)
    shading = "property float nx\nproperty float ny\nproperty float nz\n" if normals is not None else ""
    texcoords = "property float u\nproperty float v\n" if uv is not None else ""
    with open(path, "wb") as f:
        f.write(
            (
                "ply\nformat binary_little_endian 1.0\n"
                f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n{shading}{texcoords}"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
            ).encode()
        )
        rows = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
        rows["n"] = 3
        rows["i"] = faces
        f.write(verts.tobytes())
        f.write(rows.tobytes())



def errors(image, reference):
    """smlt's RMSE, relMSE and PSNR (peak 1, clamped) of image against reference."""
    d = image - reference
    n = d.size
    clamped = np.clip(image, 0, 1) - np.clip(reference, 0, 1)
    mse_c = float((clamped**2).sum() / n)
    return (
        float(np.sqrt((d**2).sum() / n)),
        float((d**2 / (reference**2 + 0.01)).sum() / n),
        10 * math.log10(1 / mse_c) if mse_c > 0 else math.inf,
    )




def time_grid(seconds):
    """The bench's measurement times: 1, 2, 4, ... below `seconds`, and `seconds`."""
    grid, t = [], 1.0
    while t < seconds:
        grid.append(t)
        t *= 2
    return grid + [seconds]


def equal_time_rows(render, chunk, seconds, repeats, reference, label, view, method):
    """The rows of an equal-time run: `repeats` renders accumulated in calls of `chunk` samples
    per pixel (`render(spp, seed)` -> (image, seconds taken), each call its own seed) and
    measured against `reference` at each time of `time_grid(seconds)`."""
    pixels = reference.shape[0] * reference.shape[1]
    rows = []
    for repeat in range(repeats):
        total = np.zeros_like(reference)
        spp, elapsed, call = 0, 0.0, 0
        for t in time_grid(seconds):
            while elapsed < t:
                img, took = render(chunk, repeat * 100003 + call)
                elapsed += took
                total += img * chunk
                spp += chunk
                call += 1
            rows.append(row(label, view, method, repeat, elapsed, spp * pixels, errors(total / spp, reference)))
            print(rows[-1], flush=True)
    return rows


def row(label, view, method, repeat, seconds, paths, err):
    rmse, relmse, psnr = err
    return (f"{label},{view},{method},{repeat},{seconds:.3f},{paths},{paths},{paths / seconds:.1f},"
            f"{paths / seconds:.1f},{rmse:.6e},{relmse:.6e},{psnr:.3f},0,nan,nan")


def append_rows(path, rows):
    """Appends rows to a results.csv (writing the header first for a new file)."""
    new = not os.path.exists(path)
    with open(path, "a") as f:
        if new:
            f.write(HEADER + "\n")
        f.write("\n".join(rows) + "\n")


def arguments(doc):
    """The arguments every peer takes (scene view, size, depth, time, repeats, reference, output)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--view", type=int, default=1)
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=72)
    ap.add_argument("--max-depth", type=int, default=10)
    ap.add_argument("--seconds", type=float, default=8.0)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--label", default=None)
    ap.add_argument("--out", default="peers.csv")
    return ap

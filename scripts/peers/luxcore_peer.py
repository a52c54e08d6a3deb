#!/usr/bin/env python3
"""LuxCoreRender as a peer of smlt's bench: `BIDIRCPU` with the `METROPOLIS` sampler (an MLT
peer) or `PATHCPU` with `SOBOL` (`--sampler` swaps them: `PATHCPU` with `METROPOLIS` is
LuxCore's Metropolis over its path tracer, as smlt's `path-` methods), on one of smlt's glTF
scene views, at equal wall time, measured against smlt's reference with smlt's error
definitions; rows in the bench's results.csv format (method `luxcore-<engine>`, `-mlt` with the
Metropolis sampler: `luxcore-bidir-mlt`, `luxcore-path`, `luxcore-path-mlt`, `luxcore-bidir`;
candidates = samples).

    python3 luxcore_peer.py SCENE.gltf --view 1 --width 128 --height 72 --max-depth 10 \\
        --engine bidir --seconds 8 --repeats 3 --reference REF.exr --label scene --out peers.csv

`--converged SECONDS` renders once that long and prints the mean against the reference and the
error of the image, of its mirror image and of the image moved by one row.

Facts this relies on (each checked here against the reference): numpy is imported before
pyluxcore (it preloads a TBB malloc proxy) and the interpreter leaves with os._exit (it
crashes at exit after a render); emitters need emission.gain 1, power and efficency 0 and
normalizebycolor false for `emission` to be radiance; `fieldofview` spans the longer image
side, so the screen window is set to [-W/H, W/H, -1, 1] with the vertical field of view; film
filter NONE and the NOP image pipeline give linear radiance, rows bottom-up, and the raster
is one row off (the window is moved by one row, `--row-shift -1`); the per-kind path depths
(`path.pathdepth.diffuse`, default 5) are raised to the total, or deep diffuse light is lost
(Sibenik rendered 30 % dark); LuxCore 2.11's Russian roulette biases it bright, so it is
switched off (path.russianroulette.depth 10000).

What it does not match: `BIDIRCPU` caps its eye subpaths (path.maxdepth) and light subpaths
(light.maxdepth) each, not their sum, and connects every eye vertex with every light vertex, so
it renders paths of up to 2 (k + 1) segments for smlt's --max-depth k; converged (40 s) it was
+4.5 % (`slit`) and +1.1 % (`sunblind`) against smlt's reference, where `PATHCPU` was -0.3 %. A
glTF BRDF that is not Lambert (Sibenik's and Sponza's) becomes LuxCore's `matte` (Sibenik +3.8 %
with `PATHCPU`; said on stderr), and smlt's Phong lobe of exponent 1e4 or more its `mirror`."""

import math
import os
import sys
import tempfile
import time

import numpy as np  # before pyluxcore

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_scene  # noqa: E402
from peer_common import append_rows, arguments, errors, row, time_grid, write_ply  # noqa: E402


def props(scene, view, width, height, max_depth, engine, sampler, folder, threads):
    cam = scene.cameras[view - 1]
    target = cam.position + cam.forward
    aspect = width / height
    v = lambda x: " ".join(f"{c:.9g}" for c in x)  # noqa: E731
    p = [
        "scene.camera.type = perspective",
        f"scene.camera.lookat.orig = {v(cam.position)}",
        f"scene.camera.lookat.target = {v(target)}",
        f"scene.camera.up = {v(cam.up)}",
        f"scene.camera.fieldofview = {math.degrees(cam.yfov)}",
        f"scene.camera.screenwindow = {-aspect} {aspect} -1 1",
    ]
    for m, tris in scene.triangles.items():
        mat = scene.materials[m]
        path = os.path.join(folder, f"mesh{m}.ply")
        write_ply(path, tris)
        if mat.phong >= 1e4:
            p.append(f"scene.materials.m{m}.type = mirror")
            p.append(f"scene.materials.m{m}.kr = {v(mat.albedo)}")
        elif mat.phong > 0:
            raise SystemExit(f"material {mat.name}: Phong exponent {mat.phong} has no LuxCore counterpart here")
        else:
            if not mat.lambertian:
                print(f"material {mat.name}: glTF's BRDF rendered as LuxCore's matte (Lambert)", file=sys.stderr)
            p.append(f"scene.materials.m{m}.type = matte")
            p.append(f"scene.materials.m{m}.kd = {v(mat.albedo)}")
        if max(mat.emission) > 0:
            p += [
                f"scene.materials.m{m}.emission = {v(mat.emission)}",
                f"scene.materials.m{m}.emission.gain = 1 1 1",
                f"scene.materials.m{m}.emission.power = 0",
                f"scene.materials.m{m}.emission.efficency = 0",
                f"scene.materials.m{m}.emission.normalizebycolor = 0",
            ]
        p.append(f"scene.objects.o{m}.ply = {path}")
        p.append(f"scene.objects.o{m}.material = m{m}")
    c = [
        f"renderengine.type = {'BIDIRCPU' if engine == 'bidir' else 'PATHCPU'}",
        f"sampler.type = {sampler.upper()}",
        f"path.maxdepth = {max_depth + 1}",
        f"path.pathdepth.total = {max_depth + 1}",
        f"path.pathdepth.diffuse = {max_depth + 1}",
        f"path.pathdepth.glossy = {max_depth + 1}",
        f"path.pathdepth.specular = {max_depth + 1}",
        f"light.maxdepth = {max_depth + 1}",
        "path.russianroulette.depth = 10000",
        f"film.width = {width}",
        f"film.height = {height}",
        "film.filter.type = NONE",
        "film.imagepipelines.0.0.type = NOP",
        f"native.threads.count = {threads}",
    ]
    return "\n".join(p), "\n".join(c)


def read_exr(path):
    import OpenEXR  # noqa: F401  (imported before pyluxcore by the caller)
    import Imath

    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    chans = [np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), dtype=np.float32) for c in "RGB"]
    return np.stack(chans, axis=-1).reshape(h, w, 3)


def main():
    ap = arguments(__doc__)
    ap.add_argument("--engine", choices=["bidir", "path"], default="bidir")
    ap.add_argument("--sampler", choices=["metropolis", "sobol"],
                    help="default: metropolis for bidir, sobol for path")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--row-shift", type=int, default=-1,
                    help="move the raster by this many rows (LuxCore 2.11's is one row off: -1, checked)")
    ap.add_argument("--converged", type=float, default=0.0)
    a = ap.parse_args()
    reference = read_exr(a.reference)
    import pyluxcore

    pyluxcore.Init(lambda msg: None)
    scene = gltf_scene.load(a.scene)
    label = a.label or os.path.splitext(os.path.basename(a.scene))[0]
    sampler = a.sampler or ("metropolis" if a.engine == "bidir" else "sobol")
    method = f"luxcore-{a.engine}" + ("-mlt" if sampler == "metropolis" else "")
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        scene_props, config = props(scene, a.view, a.width, a.height, a.max_depth, a.engine, sampler, folder, a.threads)
        if a.row_shift:
            h = 2.0 / a.height * a.row_shift
            aspect = a.width / a.height
            scene_props = scene_props.replace(
                f"scene.camera.screenwindow = {-aspect} {aspect} -1 1",
                f"scene.camera.screenwindow = {-aspect} {aspect} {-1 + h} {1 + h}",
            )
        for repeat in range(1 if a.converged else a.repeats):
            lux_scene = pyluxcore.Scene()
            lux_scene.Parse(pyluxcore.Properties().SetFromString(scene_props))
            cfg = pyluxcore.Properties().SetFromString(config + f"\nrenderengine.seed = {repeat + 1}")
            session = pyluxcore.RenderSession(pyluxcore.RenderConfig(cfg, lux_scene))
            buf = np.zeros(a.width * a.height * 3, dtype=np.float32)

            def image():
                session.UpdateStats()
                session.GetFilm().GetOutputFloat(pyluxcore.FilmOutputType.RGB_IMAGEPIPELINE, buf)
                return buf.reshape(a.height, a.width, 3)[::-1].copy()

            grid = [a.converged] if a.converged else time_grid(a.seconds)
            start = time.time()
            session.Start()
            for t in grid:
                while time.time() - start < t:
                    time.sleep(0.02)
                img = image()
                elapsed = time.time() - start
                samples = int(session.GetStats().Get("stats.renderengine.total.samplecount").GetFloat())
                if a.converged:
                    mi, mr = img.mean(), reference.mean()
                    print(
                        f"{label} v{a.view} {method}: {elapsed:.1f} s; mean {mi:.5f} against the reference's {mr:.5f}"
                        f" ({100 * (mi / mr - 1):+.2f} %); RMSE {errors(img, reference)[0]:.5f}, mirrored"
                        f" {errors(img[:, ::-1], reference)[0]:.5f}, a row up {errors(img[1:], reference[:-1])[0]:.5f},"
                        f" a row down {errors(img[:-1], reference[1:])[0]:.5f}",
                        flush=True,
                    )
                else:
                    rows.append(row(label, a.view, method, repeat, elapsed, samples, errors(img, reference)))
                    print(rows[-1], flush=True)
            session.Stop()
    if rows:
        append_rows(a.out, rows)
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()

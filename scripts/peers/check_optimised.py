#!/usr/bin/env python3
"""Files as the glTF optimisers write them: smlt on them against the same scene as written,
against an independent decoder, and against Cycles through Blender's own importer.

    python3 check_optimised.py OUT [--spp 1024] [--width 128] [--height 96] [--scene NAME=PATH ...]
        [--no-default-scenes] [--no-cycles]

The optimisers are the tools users run on their files (`npm install gltfpack @gltf-transform/cli`;
`GLTFPACK` and `GLTF_TRANSFORM` name the commands, else they are looked up on PATH):

- `gltfpack`: gltfpack 1.x with its defaults, `KHR_mesh_quantization` (positions as 14-bit
  unsigned shorts, normals and tangents as normalised signed bytes, coordinates as normalised
  unsigned shorts, the scale and offset that undo it in the nodes), meshes merged, vertices
  welded and reordered;
- `compressed`: gltfpack `-cc`, the same with every view compressed by meshoptimizer
  (`EXT_meshopt_compression`, required; the fallback buffer has no data), normals and tangents
  through the OCTAHEDRAL filter; `compressed-vpf`: `-cc -vpf`, positions as floats through the
  EXPONENTIAL filter;
- `transform`: `gltf-transform quantize` (positions as normalised signed shorts), the meshes kept;
- `transform-meshopt`: `gltf-transform meshopt`, quantised and compressed (what
  `gltf-transform optimize` does to geometry by default, without its simplification);
- `webp`: `gltf-transform webp --lossless true`, every texture as a lossless WebP
  (`EXT_texture_webp`, required, no fallback);
- `draco`: `gltf-transform draco` with its defaults, each primitive one Draco stream
  (`KHR_draco_mesh_compression`, required; Google's encoder, the `draco3dgltf` package's
  WebAssembly build: EdgeBreaker, positions on 14 bits, normals on 10, coordinates and other
  attributes on 12), vertices and faces reordered;
- `dequantized`, `decompressed` and `decompressed-vpf`: gltfpack's three files turned back into floats by
  `gltf-transform dequantize` (whose reader decodes meshoptimizer's streams with its own
  WebAssembly build of the decoder), an independent decoder of the same triangles in the same
  order; `draco-decoded`: the `draco` file decoded by Google's Draco decoder (`draco_decode.cjs`,
  the same package) and written uncompressed.

For each scene (the generated `textured`, `smooth` and `lamps` by default, plus every NAME=PATH
given: `tangents.gltf` of `tangent_scene.py` for TANGENT, Sibenik for a large mesh), in OUT/NAME/:
`float/` (the file as written) and a folder for each variant; `smlt reference` of each (--spp,
seed 1, CPU), and of the float file with seed 2 (its noise); Cycles (`cycles_peer.py --converged`)
on the float, gltfpack, transform, draco (Blender's importer decodes it with its own build of
Google's decoder) and webp files, and (Blender 5.0's importer refuses `EXT_meshopt_compression`)
on the decompressed one.

Printed a scene: the attribute types of the quantised files; the warnings smlt gave; smlt on
gltfpack's files against smlt on their decoded twins (same triangles, same random numbers: only
the decoders' last-bit differences); each variant against the float file (mean difference, RMSE,
beside the noise's RMSE: quantisation moves every vertex by up to 2^-15 of the scene's size);
Cycles against smlt on each file, and Cycles on each variant against Cycles on the float file.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from cycles_peer import read_exr  # noqa: E402

VARIANTS = ("gltfpack", "compressed", "compressed-vpf", "transform", "transform-meshopt", "webp", "draco",
            "dequantized", "decompressed", "decompressed-vpf", "draco-decoded")
TYPES = {5120: "i8", 5121: "u8", 5122: "i16", 5123: "u16", 5125: "u32", 5126: "f32"}


def tool(env, name):
    path = os.environ.get(env) or shutil.which(name)
    if not path:
        raise SystemExit(f"{name} not found: npm install gltfpack @gltf-transform/cli, or set {env}")
    return path


def node_modules():
    """The node_modules folder glTF-Transform was installed in (NODE_PATH, else its command's)."""
    return os.environ.get("NODE_PATH") or os.path.dirname(os.path.dirname(tool("GLTF_TRANSFORM", "gltf-transform")))


def run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(map(str, cmd))} failed:\n{p.stdout}{p.stderr}")
    return p.stdout + p.stderr


def attribute_types(path):
    """Each attribute's accessor types in the file, e.g. {'POSITION': {'u16'}, 'NORMAL': {'i8 n'}}."""
    with open(path) as f:
        doc = json.load(f)
    out = {}
    for mesh in doc.get("meshes", []):
        for prim in mesh["primitives"]:
            for name, k in prim["attributes"].items():
                a = doc["accessors"][k]
                out.setdefault(name, set()).add(TYPES[a["componentType"]] + (" n" if a.get("normalized") else ""))
    return {k: "/".join(sorted(v)) for k, v in sorted(out.items())}


def smlt_binary():
    """The release build of smlt (CARGO_TARGET_DIR honoured)."""
    return os.path.join(os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "smlt")


def smlt_reference(smlt, path, exr, spp, seed, size):
    """`smlt reference` of `path` on the CPU (`size` its size flags) written to `exr`: the image and
    the warning lines smlt printed."""
    log = run([smlt, "reference", path, "--device", "cpu", "--spp", str(spp), "--seed", str(seed), "--out", exr,
               *size])
    return read_exr(exr), [line.strip() for line in log.splitlines() if "warning" in line.lower()]


def peer_check_args(spp, width, height):
    """The command line of a check beside Cycles (OUT, --spp, --cycles-samples, --width,
    --height, with these defaults): the parsed arguments, and smlt's size flags (max depth 10)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--spp", type=int, default=spp)
    ap.add_argument("--cycles-samples", type=int, default=1024)
    ap.add_argument("--width", type=int, default=width)
    ap.add_argument("--height", type=int, default=height)
    a = ap.parse_args()
    return a, ["--width", str(a.width), "--height", str(a.height), "--max-depth", "10"]


def printed_reference(smlt, path, exr, spp, seed, size, key):
    """`smlt_reference`, its warnings printed as the `key` file's: the image."""
    image, warnings = smlt_reference(smlt, path, exr, spp, seed, size)
    for line in warnings:
        print(f"  smlt warned on {key}: {line}")
    return image


def compare(image, against):
    """Mean difference (per cent of `against`'s mean) and RMSE."""
    rmse = float(np.sqrt(((image - against) ** 2).mean()))
    return 100 * (image.mean() / against.mean() - 1), rmse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=96)
    ap.add_argument("--max-depth", type=int, default=10)
    ap.add_argument("--scene", action="append", default=[], help="NAME=PATH of a .gltf to check too")
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--no-default-scenes", action="store_true", help="only the --scene ones")
    a = ap.parse_args()
    smlt = smlt_binary()
    gltfpack, transform = tool("GLTFPACK", "gltfpack"), tool("GLTF_TRANSFORM", "gltf-transform")
    size = ["--width", str(a.width), "--height", str(a.height), "--max-depth", str(a.max_depth)]
    print(f"gltfpack {run([gltfpack, '-v']).split()[1]}, glTF-Transform {run([transform, '--version']).strip()}; "
          f"smlt reference {a.spp} spp, {a.width}x{a.height}, max depth {a.max_depth}")
    defaults = [] if a.no_default_scenes else [(n, None) for n in ("textured", "smooth", "lamps")]
    scenes = defaults + [tuple(s.split("=", 1)) for s in a.scene]
    for name, source in scenes:
        folder = os.path.join(a.out, name)
        paths = {k: os.path.join(folder, k, "scene.gltf") for k in ("float", *VARIANTS)}
        for p in paths.values():
            os.makedirs(os.path.dirname(p), exist_ok=True)
        if source is None:
            run([smlt, "scene", name, "--out", paths["float"]])
        else:
            # A copy that keeps the file's relative URIs: its folder's files beside it.
            src = os.path.dirname(os.path.abspath(source))
            shutil.copytree(src, os.path.dirname(paths["float"]), dirs_exist_ok=True)
            shutil.copyfile(source, paths["float"])
        run([gltfpack, "-i", paths["float"], "-o", paths["gltfpack"]])
        run([gltfpack, "-cc", "-i", paths["float"], "-o", paths["compressed"]])
        run([gltfpack, "-cc", "-vpf", "-i", paths["float"], "-o", paths["compressed-vpf"]])
        run([transform, "quantize", paths["float"], paths["transform"]])
        run([transform, "meshopt", paths["float"], paths["transform-meshopt"]])
        run([transform, "webp", "--lossless", "true", paths["float"], paths["webp"]])
        run([transform, "dequantize", paths["gltfpack"], paths["dequantized"]])
        run([transform, "dequantize", paths["compressed"], paths["decompressed"]])
        run([transform, "dequantize", paths["compressed-vpf"], paths["decompressed-vpf"]])
        run([transform, "draco", paths["float"], paths["draco"]])
        run(["node", os.path.join(HERE, "draco_decode.cjs"), paths["draco"], paths["draco-decoded"]],
            env={**os.environ, "NODE_PATH": node_modules()})

        def reference(key, seed=1):
            return smlt_reference(smlt, paths[key], os.path.join(folder, f"smlt_{key}_{seed}.exr"), a.spp, seed, size)

        images, warned = {}, {}
        for key in paths:
            images[key], warned[key] = reference(key)
        noise = compare(reference("float", 2)[0], images["float"])[1]
        print(f"\n{name}: mean {images['float'].mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
        for key in ("gltfpack", "transform", "transform-meshopt", "draco"):
            print(f"  {key}: {attribute_types(paths[key])}")
        for key, lines in warned.items():
            for line in lines:
                print(f"  smlt warned on {key}: {line.strip()}")
        for key, twin in (
            ("gltfpack", "dequantized"),
            ("compressed", "decompressed"),
            ("compressed-vpf", "decompressed-vpf"),
            ("draco", "draco-decoded"),
        ):
            q, d = images[key], images[twin]
            same = float((q == d).all(-1).mean())
            print(f"  smlt on {key} against the {twin} file: {100 * same:.1f} % of pixels identical, "
                  f"mean {compare(q, d)[0]:+.4f} %, RMSE {compare(q, d)[1]:.2e}")
        for key in ("gltfpack", "compressed", "compressed-vpf", "transform", "transform-meshopt", "webp", "draco"):
            dm, r = compare(images[key], images["float"])
            print(f"  {key} against the float file: mean {dm:+.3f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)")
        if a.no_cycles:
            continue
        cycles = {}
        with open(paths["float"]) as f:
            textured = bool(json.load(f).get("images"))
        # Blender 5.0 refuses EXT_meshopt_compression: its decoded twin stands in for gltfpack -cc.
        for key in ("float", "gltfpack", "decompressed", "transform", "draco") + (("webp",) if textured else ()):
            exr = os.path.join(folder, f"cycles_{key}.exr")
            run([sys.executable, os.path.join(HERE, "cycles_peer.py"), paths[key], "--converged", str(a.spp),
                 "--reference", os.path.join(folder, f"smlt_{key}_1.exr"), "--save", exr, *size])
            cycles[key] = read_exr(exr)
            dm, r = compare(cycles[key], images[key])
            line = f"  Cycles on the {key} file: against smlt on it mean {dm:+.3f} %, RMSE {r:.2e}"
            if key != "float":
                dm, r = compare(cycles[key], cycles["float"])
                line += f"; against Cycles on the float file mean {dm:+.3f} %, RMSE {r:.2e}"
            print(line)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Blender's own glTF exporter with its Draco mesh compression: smlt on the compressed file
against the same scene exported uncompressed, against Google's decoder, and against Cycles.

    python3 check_blender_draco.py OUT [--spp 4096] [--cycles-samples 1024] [--width 160] [--height 120]

Needs the peers' Python packages (`bpy`), smlt built (`cargo build --release`; CARGO_TARGET_DIR
is honoured) and `npm install @gltf-transform/cli` (NODE_PATH, or GLTF_TRANSFORM or PATH to find
its node_modules).

The scene is the lamp-lit one of `blender_round_trip.py` (checker floor, wall, red box, gold
ball, glass ball; a point lamp, a spot and a sun), built in Blender and exported twice:
`OUT/plain/` as written, `OUT/draco/` with `export_draco_mesh_compression_enable` and the
exporter's defaults (level 6; positions on 14 bits, normals on 10, coordinates on 12), each
rendered by Cycles through Blender's own importer (`blender_round_trip.cycles`, whose importer
decodes Draco with Blender's build of Google's decoder). `OUT/decoded/` is the Draco file read by
Google's decoder (`draco_decode.cjs`) and written uncompressed. smlt's path tracer renders the
three (`smlt reference`, seed 1; the plain file with seed 2 too, for its noise).

Printed: smlt on the Draco file against the decoded one (the same triangles in the same order:
any difference is the decoders'); smlt and Cycles each on the Draco file against the plain one
(what the quantisation changes, as each renderer sees it); Cycles against smlt on each file.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import blender_round_trip  # noqa: E402
from check_optimised import compare, node_modules, peer_check_args, printed_reference, run, smlt_binary  # noqa: E402
from cycles_peer import read_exr  # noqa: E402


def main():
    a, size = peer_check_args(4096, 160, 120)
    smlt = smlt_binary()
    files = {}
    for key in ("plain", "draco"):
        folder = os.path.join(a.out, key)
        os.makedirs(folder, exist_ok=True)
        files[key] = blender_round_trip.build(folder, draco=key == "draco")
        blender_round_trip.cycles(folder, files[key], a.cycles_samples, a.width, a.height)
    files["decoded"] = os.path.join(a.out, "decoded", "round_trip.gltf")
    run(["node", os.path.join(HERE, "draco_decode.cjs"), files["draco"], files["decoded"]],
        env={**os.environ, "NODE_PATH": node_modules()})

    def reference(key, seed=1):
        exr = os.path.join(a.out, f"smlt_{key}_{seed}.exr")
        return printed_reference(smlt, files[key], exr, a.spp, seed, size, key)

    import bpy

    print(f"Blender {bpy.app.version_string}; smlt reference {a.spp} spp, Cycles {a.cycles_samples} spp, "
          f"{a.width}x{a.height}, max depth 10")
    smlt_images = {key: reference(key) for key in files}
    noise = compare(reference("plain", 2), smlt_images["plain"])[1]
    cycles = {key: read_exr(os.path.join(a.out, key, "cycles.exr")) for key in ("plain", "draco")}
    print(f"smlt on the plain file: mean {smlt_images['plain'].mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
    d, q = smlt_images["draco"], smlt_images["decoded"]
    same = float((d == q).all(-1).mean())
    print(f"  smlt on the Draco file against the decoded one: {100 * same:.1f} % of pixels identical, "
          f"mean {compare(d, q)[0]:+.4f} %, RMSE {compare(d, q)[1]:.2e}")
    dm, r = compare(smlt_images["draco"], smlt_images["plain"])
    print(f"  smlt on the Draco file against the plain one: mean {dm:+.3f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)")
    dm, r = compare(cycles["draco"], cycles["plain"])
    print(f"  Cycles on the Draco file against the plain one: mean {dm:+.3f} %, RMSE {r:.2e}")
    for key in ("plain", "draco"):
        dm, r = compare(cycles[key], smlt_images[key])
        print(f"  Cycles against smlt on the {key} file: mean {dm:+.3f} %, RMSE {r:.2e}")


if __name__ == "__main__":
    main()

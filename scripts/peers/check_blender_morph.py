#!/usr/bin/env python3
"""Blender's shape keys as its glTF exporter writes them (morph targets with the keys' values as
the mesh's weights): smlt on the file against Blender's own evaluation of the same keys, and
against Cycles.

    python3 check_blender_morph.py OUT [--spp 4096] [--cycles-samples 1024] [--width 160] [--height 120]

Needs the peers' Python packages (`bpy`) and smlt built (`cargo build --release`; CARGO_TARGET_DIR
is honoured).

The scene is the plain lamp-lit one of `blender_round_trip.py` (no glass), its white ball given two
shape keys, "squash" at 0.7 and "lift" at 0 (`add_shape_keys`), built in Blender and exported
twice: `OUT/targets/` as the exporter writes the keys (two morph targets, weights [0.7, 0]),
`OUT/baked/` with the ball's mesh replaced by Blender's evaluation of the mix (no keys). Each is
rendered by smlt (`smlt reference`, seed 1; the baked file with seed 2 too, for its noise) and by
Cycles through Blender's importer, which makes the targets shape keys again at the weights' values.

Printed: smlt on the morph-target file against the baked one (the same geometry: any difference
is the two evaluations' rounding), the ball's extent as smlt reads it, and Cycles against smlt.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from check_optimised import compare, peer_check_args, printed_reference, smlt_binary  # noqa: E402
from blender_round_trip import in_own_python  # noqa: E402
from cycles_peer import read_exr  # noqa: E402


def main():
    a, size = peer_check_args(4096, 160, 120)
    smlt = smlt_binary()
    files = {}
    for key in ("targets", "baked"):
        folder = os.path.join(a.out, key)
        os.makedirs(folder, exist_ok=True)
        files[key] = os.path.join(folder, "round_trip.gltf")
        in_own_python(f"blender_round_trip.build({folder!r}, glass=False, plain=True, shape_keys={key!r})")
        in_own_python(f"blender_round_trip.cycles({folder!r}, {files[key]!r}, {a.cycles_samples}, {a.width}, {a.height})")
    import json

    with open(files["targets"]) as f:
        doc = json.load(f)
    ball = [m for m in doc["meshes"] if m["primitives"][0].get("targets")]
    print(f"the morph-target file: {ball[0]['name']} with {len(ball[0]['primitives'][0]['targets'])} targets, "
          f"weights {ball[0].get('weights')}")

    def reference(key, seed=1):
        exr = os.path.join(a.out, f"smlt_{key}_{seed}.exr")
        return printed_reference(smlt, files[key], exr, a.spp, seed, size, key)

    images = {key: reference(key) for key in files}
    noise = compare(reference("baked", 2), images["baked"])[1]
    t, b = images["targets"], images["baked"]
    same = float((t == b).all(-1).mean())
    print(f"smlt on the baked file: mean {b.mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
    dm, r = compare(t, b)
    print(f"  smlt on the morph-target file against the baked one: {100 * same:.1f} % of pixels identical, "
          f"mean {dm:+.4f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)")
    cycles = {key: read_exr(os.path.join(a.out, key, "cycles.exr")) for key in files}
    dm, r = compare(cycles["targets"], cycles["baked"])
    print(f"  Cycles on the morph-target file against the baked one: mean {dm:+.3f} %, RMSE {r:.2e}")
    for key in files:
        dm, r = compare(cycles[key], images[key])
        print(f"  Cycles against smlt on the {key} file: mean {dm:+.3f} %, RMSE {r:.2e}")


if __name__ == "__main__":
    main()

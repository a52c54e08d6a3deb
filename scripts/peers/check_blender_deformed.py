#!/usr/bin/env python3
"""A mesh Blender deforms, as its glTF exporter writes it: smlt on the file against Blender's own
evaluation of the same deformation, and against Cycles. Two deformations (DEFORMATION):
`shape_keys` (morph targets with the keys' values as the mesh's weights) and `armature` (a skin
whose joints hold the pose).

    python3 check_blender_deformed.py {shape_keys,armature} OUT [--spp 4096] [--cycles-samples 1024]
        [--width 160] [--height 120]

Needs the peers' Python packages (`bpy`) and smlt built (`cargo build --release`; CARGO_TARGET_DIR
is honoured).

The scene is the plain lamp-lit one of `blender_round_trip.py` (no glass), its white ball
deformed, built in Blender and exported twice:
- `shape_keys`: two shape keys, "squash" at 0.7 and "lift" at 0 (`add_shape_keys`).
  `OUT/targets/` as the exporter writes the keys (two morph targets, weights [0.7, 0]).
- `armature`: a two-bone armature, posed (`add_armature`). `OUT/posed/` as the exporter writes it
  with the pose (a skin of two joints).
- `OUT/baked/`: either with the ball's mesh replaced by Blender's evaluation of the deformation.
Each is rendered by smlt (`smlt reference`, seed 1; the baked file with seed 2 too, for its noise)
and by Cycles through Blender's importer, which makes the targets shape keys again at the weights'
values, and the skin an armature in the joints' pose.

Printed: smlt on the deformed file against the baked one (the same vertices; any difference is
the normals, and the evaluations' rounding), and Cycles against smlt.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from check_optimised import compare, peer_check_args, printed_reference, smlt_binary  # noqa: E402
from blender_round_trip import in_own_python  # noqa: E402
from cycles_peer import read_exr  # noqa: E402


# Each deformation: the name of the deformed file's folder, and the `build` argument.
DEFORMED = {"shape_keys": "targets", "armature": "posed"}


def main():
    deformation = sys.argv.pop(1) if len(sys.argv) > 1 and sys.argv[1] in DEFORMED else None
    if deformation is None:
        sys.exit(f"usage: check_blender_deformed.py {{{','.join(DEFORMED)}}} OUT [options]")
    a, size = peer_check_args(4096, 160, 120)
    smlt = smlt_binary()
    deformed = DEFORMED[deformation]
    files = {}
    for key in (deformed, "baked"):
        folder = os.path.join(a.out, key)
        os.makedirs(folder, exist_ok=True)
        files[key] = os.path.join(folder, "round_trip.gltf")
        in_own_python(f"blender_round_trip.build({folder!r}, glass=False, plain=True, {deformation}={key!r})")
        in_own_python(f"blender_round_trip.cycles({folder!r}, {files[key]!r}, {a.cycles_samples}, {a.width}, {a.height})")
    import json

    with open(files[deformed]) as f:
        doc = json.load(f)
    if deformation == "shape_keys":
        ball = [m for m in doc["meshes"] if m["primitives"][0].get("targets")]
        print(f"the morph-target file: {ball[0]['name']} with {len(ball[0]['primitives'][0]['targets'])} targets, "
              f"weights {ball[0].get('weights')}")
    else:
        skins = doc.get("skins", [])
        print(f"the skinned file: {len(skins)} skin(s), joints {[s['joints'] for s in skins]}")

    def reference(key, seed=1):
        exr = os.path.join(a.out, f"smlt_{key}_{seed}.exr")
        return printed_reference(smlt, files[key], exr, a.spp, seed, size, key)

    images = {key: reference(key) for key in files}
    noise = compare(reference("baked", 2), images["baked"])[1]
    t, b = images[deformed], images["baked"]
    same = float((t == b).all(-1).mean())
    print(f"smlt on the baked file: mean {b.mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
    dm, r = compare(t, b)
    print(f"  smlt on the {deformed} file against the baked one: {100 * same:.1f} % of pixels identical, "
          f"mean {dm:+.4f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)")
    cycles = {key: read_exr(os.path.join(a.out, key, "cycles.exr")) for key in files}
    dm, r = compare(cycles[deformed], cycles["baked"])
    print(f"  Cycles on the {deformed} file against the baked one: mean {dm:+.3f} %, RMSE {r:.2e}")
    for key in files:
        dm, r = compare(cycles[key], images[key])
        print(f"  Cycles against smlt on the {key} file: mean {dm:+.3f} %, RMSE {r:.2e}")


if __name__ == "__main__":
    main()

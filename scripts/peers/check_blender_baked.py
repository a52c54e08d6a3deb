#!/usr/bin/env python3
"""A mesh feature as Blender's glTF exporter writes it, against Blender's own baking of it into
plain glTF: smlt on each file, and Cycles on each. Three features (FEATURE): `shape_keys` (morph
targets with the keys' values as the mesh's weights), `armature` (a skin whose joints hold the
pose) and `vertex_colors` (a colour attribute the material reads, as COLOR_0).

    python3 check_blender_baked.py {shape_keys,armature,vertex_colors} OUT [--spp 4096]
        [--cycles-samples 1024] [--width 160] [--height 120]

Needs the peers' Python packages (`bpy`) and smlt built (`cargo build --release`; CARGO_TARGET_DIR
is honoured).

The scene is the plain lamp-lit one of `blender_round_trip.py` (no glass), its white ball given
the feature, built in Blender and exported twice:
- `shape_keys`: two shape keys, "squash" at 0.7 and "lift" at 0 (`add_shape_keys`).
  `OUT/targets/` as the exporter writes the keys (two morph targets, weights [0.7, 0]).
- `armature`: a two-bone armature, posed (`add_armature`). `OUT/posed/` as the exporter writes it
  with the pose (a skin of two joints).
- `vertex_colors`: its faces in four colours (`add_vertex_colors`). `OUT/attribute/` as a colour
  attribute its material reads (COLOR_0).
- `OUT/baked/`: the same scene baked: for the deformations, the ball's mesh replaced by Blender's
  evaluation of it; for the colours, four materials of those base colours, one a face.
Each is rendered by smlt (`smlt reference`, seed 1; the baked file with seed 2 too, for its noise)
and by Cycles through Blender's importer, which makes the targets shape keys again at the weights'
values, the skin an armature in the joints' pose, and COLOR_0 a colour attribute its material
reads.

Printed: smlt on the file against the baked one (the same scene: for the deformations any
difference is the normals and the evaluations' rounding, for the colours the interpolation's
rounding), and Cycles against smlt.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from check_optimised import compare, peer_check_args, printed_reference, smlt_binary  # noqa: E402
from blender_round_trip import in_own_python  # noqa: E402
from cycles_peer import read_exr  # noqa: E402


# Each feature (a `build` argument): the name of its file's folder (the argument's value).
FEATURES = {"shape_keys": "targets", "armature": "posed", "vertex_colors": "attribute"}


def main():
    feature = sys.argv.pop(1) if len(sys.argv) > 1 and sys.argv[1] in FEATURES else None
    if feature is None:
        sys.exit(f"usage: check_blender_baked.py {{{','.join(FEATURES)}}} OUT [options]")
    a, size = peer_check_args(4096, 160, 120)
    smlt = smlt_binary()
    featured = FEATURES[feature]
    files = {}
    for key in (featured, "baked"):
        folder = os.path.join(a.out, key)
        os.makedirs(folder, exist_ok=True)
        files[key] = os.path.join(folder, "round_trip.gltf")
        in_own_python(f"blender_round_trip.build({folder!r}, glass=False, plain=True, {feature}={key!r})")
        in_own_python(f"blender_round_trip.cycles({folder!r}, {files[key]!r}, {a.cycles_samples}, {a.width}, {a.height})")
    import json

    with open(files[featured]) as f:
        doc = json.load(f)
    if feature == "shape_keys":
        ball = [m for m in doc["meshes"] if m["primitives"][0].get("targets")]
        print(f"the morph-target file: {ball[0]['name']} with {len(ball[0]['primitives'][0]['targets'])} targets, "
              f"weights {ball[0].get('weights')}")
    elif feature == "armature":
        skins = doc.get("skins", [])
        print(f"the skinned file: {len(skins)} skin(s), joints {[s['joints'] for s in skins]}")
    else:
        coloured = [m["name"] for m in doc["meshes"] if "COLOR_0" in m["primitives"][0]["attributes"]]
        print(f"the coloured file: COLOR_0 on {coloured}")

    def reference(key, seed=1):
        exr = os.path.join(a.out, f"smlt_{key}_{seed}.exr")
        return printed_reference(smlt, files[key], exr, a.spp, seed, size, key)

    images = {key: reference(key) for key in files}
    noise = compare(reference("baked", 2), images["baked"])[1]
    t, b = images[featured], images["baked"]
    same = float((t == b).all(-1).mean())
    print(f"smlt on the baked file: mean {b.mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
    dm, r = compare(t, b)
    print(f"  smlt on the {featured} file against the baked one: {100 * same:.1f} % of pixels identical, "
          f"mean {dm:+.4f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)")
    cycles = {key: read_exr(os.path.join(a.out, key, "cycles.exr")) for key in files}
    dm, r = compare(cycles[featured], cycles["baked"])
    print(f"  Cycles on the {featured} file against the baked one: mean {dm:+.3f} %, RMSE {r:.2e}")
    for key in files:
        dm, r = compare(cycles[key], images[key])
        print(f"  Cycles against smlt on the {key} file: mean {dm:+.3f} %, RMSE {r:.2e}")


if __name__ == "__main__":
    main()

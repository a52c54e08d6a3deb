#!/usr/bin/env python3
"""KTX2 textures (`KHR_texture_basisu`) as Binomial's Basis Universal encoder writes them: smlt on
the compressed file against its twin decoded by Binomial's own transcoder, against the scene as
written, and against Cycles.

    python3 check_ktx2.py OUT [--spp 1024] [--cycles-samples 1024] [--width 128] [--height 96]

Needs the peers' Python packages (`bpy`), smlt built (`cargo build --release`; CARGO_TARGET_DIR
is honoured) and `npm install @gltf-transform/cli ktx2-encoder@0.6.0 three@0.170.0` (NODE_PATH,
or GLTF_TRANSFORM or PATH to find its node_modules).

Scenes, each in OUT/NAME/float/ as written: `textured` (`smlt scene textured`: four small
base-colour and emissive textures), `normal_map` (`normal_map_scene.py`: a 16x4 normal map under
a sun) and `round_trip` (Blender 5.0's own export of `blender_round_trip.py`'s lamp-lit scene, a
64x64 checker on its floor). Variants (`ktx2_encode.mjs`): `etc1s` (ETC1S with BasisLZ, every mip
level) and `uastc_zstd` (UASTC with Zstandard); `*-decoded` (`ktx2_decode.cjs`) the same file with
each image transcoded by Binomial's transcoder (three.js's WebAssembly build) and written as PNG.
smlt's path tracer renders every file (`smlt reference`, seed 1; the float file with seed 2 too,
for its noise); Cycles, through Blender's importer (which does not read KTX2), the float file and
the decoded twins (`blender_round_trip.cycles`).

Printed a scene: smlt on each KTX2 file against its decoded twin (the same texels: any difference
is the transcoders'); each variant against the float file, as smlt and as Cycles see it (what the
compression changes); Cycles on each twin against smlt on the KTX2 file.
"""
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from check_optimised import compare, node_modules, peer_check_args, printed_reference, run, smlt_binary  # noqa: E402
from blender_round_trip import in_own_python  # noqa: E402
from cycles_peer import read_exr  # noqa: E402

VARIANTS = {"etc1s": ["--mipmaps"], "uastc_zstd": ["--uastc", "--zstd"]}


def source(name, folder, smlt):
    """Writes scene `name` into `folder`; its .gltf."""
    os.makedirs(folder, exist_ok=True)
    if name == "textured":
        path = os.path.join(folder, "scene.gltf")
        run([smlt, "scene", "textured", "--out", path])
        return path
    if name == "normal_map":
        run([sys.executable, os.path.join(HERE, "normal_map_scene.py"), folder])
        return os.path.join(folder, "normal_map.gltf")
    # Blender's export, as check_blender_draco.py makes it (in a process of its own: bpy).
    return in_own_python(f"print(blender_round_trip.build({folder!r}))").strip().splitlines()[-1]


def main():
    a, size = peer_check_args(1024, 128, 96)
    smlt = smlt_binary()
    env = {**os.environ, "NODE_PATH": node_modules()}
    import bpy

    print(f"Blender {bpy.app.version_string}; smlt reference {a.spp} spp, Cycles {a.cycles_samples} spp, "
          f"{a.width}x{a.height}, max depth 10")
    for name in ("textured", "normal_map", "round_trip"):
        folder = os.path.join(a.out, name)
        shutil.rmtree(folder, ignore_errors=True)
        files = {"float": source(name, os.path.join(folder, "float"), smlt)}
        for variant, flags in VARIANTS.items():
            files[variant] = os.path.join(folder, variant, "scene.gltf")
            files[f"{variant}-decoded"] = os.path.join(folder, f"{variant}-decoded", "scene.gltf")
            run(["node", os.path.join(HERE, "ktx2_encode.mjs"), files["float"], files[variant], *flags], env=env)
            run(["node", os.path.join(HERE, "ktx2_decode.cjs"), files[variant], files[f"{variant}-decoded"]], env=env)

        def reference(key, seed=1):
            exr = os.path.join(folder, f"smlt_{key}_{seed}.exr")
            return printed_reference(smlt, files[key], exr, a.spp, seed, size, key)

        images = {key: reference(key) for key in files}
        noise = compare(reference("float", 2), images["float"])[1]
        cycles = {}
        for key in ("float", *(f"{v}-decoded" for v in VARIANTS)):
            out = os.path.join(folder, f"cycles_{key}")
            os.makedirs(out, exist_ok=True)
            in_own_python(f"blender_round_trip.cycles({out!r}, {files[key]!r}, {a.cycles_samples}, {a.width}, "
                          f"{a.height})")
            cycles[key] = read_exr(os.path.join(out, "cycles.exr"))
        print(f"\n{name}: smlt on the float file mean {images['float'].mean():.5f}, noise RMSE (seeds 1, 2) {noise:.2e}")
        for variant in VARIANTS:
            k, d = images[variant], images[f"{variant}-decoded"]
            same = float((k == d).all(-1).mean())
            print(f"  {variant}: smlt on the KTX2 file against Binomial's decoding of it: {100 * same:.1f} % of "
                  f"pixels identical, mean {compare(k, d)[0]:+.4f} %, RMSE {compare(k, d)[1]:.2e}")
            dm, r = compare(k, images["float"])
            line = f"    against the float file: smlt mean {dm:+.3f} %, RMSE {r:.2e} ({r / noise:.2f} x the noise)"
            dm, r = compare(cycles[f"{variant}-decoded"], cycles["float"])
            print(f"{line}; Cycles (decoded twin) mean {dm:+.3f} %, RMSE {r:.2e}")
            dm, r = compare(cycles[f"{variant}-decoded"], k)
            print(f"    Cycles on the decoded twin against smlt on the KTX2 file: mean {dm:+.3f} %, RMSE {r:.2e}")
        dm, r = compare(cycles["float"], images["float"])
        print(f"  Cycles against smlt on the float file: mean {dm:+.3f} %, RMSE {r:.2e}")


if __name__ == "__main__":
    main()

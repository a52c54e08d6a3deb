#!/usr/bin/env python3
"""Writes the normal-map check scene: a Lambertian floor (albedo 0.8) whose normalTexture has
four bands across the image, lit by a sun, seen from above. Written from the glTF spec, not
from smlt's code, for `check_normal_map.sh`.

    python3 normal_map_scene.py OUT_FOLDER [--tilt DEGREES] [--scale S]

OUT_FOLDER gets `normal_map.gltf`, `normal_map.bin` and `normal_map.png` (16 x 4 texels, linear
RGB, NEAREST). The bands, left to right in the image (u = 0..1): flat (0, 0, 1); leaning +x;
leaning +y; leaning -y, each by --tilt degrees (default 30) in tangent space, written as
rgb = (n + 1) / 2 in 8 bits. The floor is the square -1..1 in x and z at y = 0, facing +y, with
TEXCOORD_0 u = (x + 1) / 2 and v = (z + 1) / 2, so that the image's +x lies along world +x and its
+y (up in the image: decreasing v, as glTF's v runs down) along world -z. The sun shines from
above and from -z (its light travels along (0, -cos a, sin a), a = 40 degrees): a +y band leans
towards it and is brighter than the flat one, a -y band darker, a +x band darker (it leans
sideways). With --scale the texture's normalTexture.scale is written too (x and y scaled).
"""

import argparse
import json
import math
import os
import struct
import zlib


def png(width, height, rows):
    """An 8-bit RGB PNG of `rows` (lists of (r, g, b) bytes, top row first)."""
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def texel(n):
    """A tangent-space unit normal as the spec stores it: round((n + 1) / 2 * 255)."""
    return tuple(int(round((c + 1.0) / 2.0 * 255.0)) for c in n)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--tilt", type=float, default=30.0)
    ap.add_argument("--scale", type=float, default=None)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    s, c = math.sin(math.radians(a.tilt)), math.cos(math.radians(a.tilt))
    bands = [(0.0, 0.0, 1.0), (s, 0.0, c), (0.0, s, c), (0.0, -s, c)]
    row = [texel(bands[i // 4]) for i in range(16)]
    with open(os.path.join(a.out, "normal_map.png"), "wb") as f:
        f.write(png(16, 4, [row] * 4))

    # The floor: two triangles, counter-clockwise seen from +y.
    positions = [(-1.0, 0.0, -1.0), (1.0, 0.0, -1.0), (1.0, 0.0, 1.0), (-1.0, 0.0, 1.0)]
    uvs = [((x + 1.0) / 2.0, (z + 1.0) / 2.0) for x, _, z in positions]
    indices = [0, 2, 1, 0, 3, 2]
    blob = b"".join(struct.pack("<3f", *p) for p in positions)
    blob += b"".join(struct.pack("<2f", *t) for t in uvs)
    blob += struct.pack("<6H", *indices) + b"\0\0"
    sun = math.radians(40.0)
    # The light travels along the node's -z, here turned to (0, -cos a, sin a) by a rotation
    # about x of -(90 deg + a), written as a quaternion (x, y, z, w).
    angle = -(math.pi / 2.0 + sun)
    sun_rotation = [math.sin(angle / 2.0), 0.0, 0.0, math.cos(angle / 2.0)]
    # The camera looks straight down (its -z along world -y): a rotation of -90 deg about x.
    down = [-math.sin(math.pi / 4.0), 0.0, 0.0, math.cos(math.pi / 4.0)]
    normal_texture = {"index": 0}
    if a.scale is not None:
        normal_texture["scale"] = a.scale
    doc = {
        "asset": {"version": "2.0", "generator": "smlt scripts/peers/normal_map_scene.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0}]}},
        "buffers": [{"byteLength": len(blob), "uri": "normal_map.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32, "target": 34962},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12, "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, 0.0, -1.0], "max": [1.0, 0.0, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "images": [{"uri": "normal_map.png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "textures": [{"sampler": 0, "source": 0}],
        "materials": [{
            "name": "floor",
            "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "normalTexture": normal_texture,
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}},
        }],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                    "material": 0}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01, "aspectRatio": 1.6}}],
        "nodes": [
            {"mesh": 0, "name": "floor"},
            {"camera": 0, "translation": [0.0, 2.2, 0.0], "rotation": down, "name": "camera"},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": sun_rotation, "name": "sun"},
        ],
        "scenes": [{"nodes": [0, 1, 2]}],
        "scene": 0,
    }
    with open(os.path.join(a.out, "normal_map.bin"), "wb") as f:
        f.write(blob)
    with open(os.path.join(a.out, "normal_map.gltf"), "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()

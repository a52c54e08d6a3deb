"""The peers' plate scenes: one material on a plate 16 m wide, seen from (0, 1.2, 1.2) looking
at the origin (yfov 0.5: the plate fills the view), lit by a sun of 683 lux (1 W/m²) from
(0.4, 1, 0.3) — one bounce, whose image is the BSDF at each pixel's two directions times the
sun's irradiance (check_materials.sh, check_clearcoat.sh).

    import plate_scene; plate_scene.write("plate_gold.gltf", "gold", {"metallicFactor": 1.0}, {})

`exact_image` evaluates a plate's exact image through Mitsuba (any BSDF, the plugins too).
"""

import base64
import json
import math
import struct
import zlib

CORNERS = [(-8, 0, 8), (8, 0, 8), (8, 0, -8), (-8, 0, -8)]
TO_SUN = (0.4, 1.0, 0.3)


def _sun_rotation(to_sun):
    """The quaternion taking the node's −Z (where a glTF light shines) to the direction of a sun
    that lies towards `to_sun`."""
    n = math.sqrt(sum(c * c for c in to_sun))
    d = [-c / n for c in to_sun]
    axis = [d[1], -d[0], 0.0]  # (−Z) × d
    s = math.sqrt(sum(c * c for c in axis))
    angle = math.acos(-d[2])
    return [c / s * math.sin(angle / 2) for c in axis] + [math.cos(angle / 2)]


def _png(rgba):
    """A 1 × 1 PNG of the 8-bit RGBA `rgba`."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    header = struct.pack(">IIBBBBB", 1, 1, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"\x00" + bytes(rgba)))
            + chunk(b"IEND", b""))


def write(path, name, pbr, extensions, mapped=False, texel=None, to_sun=TO_SUN):
    """Writes the plate of material `name` (its pbrMetallicRoughness `pbr` and material
    `extensions`) to `path`; `mapped`: with NORMAL (+Y) and TEXCOORD_0 (u along +x, v along +z,
    [0, 1] over the plate), the tangent frame of KHR_materials_anisotropy (FRAME); `texel`: the
    8-bit RGBA of texture 0, 1 × 1 and nearest, for `extensions` to name; `to_sun`: where the
    sun lies (below the plate, y < 0, for a glass plate's transmission)."""
    data = b"".join(struct.pack("<3f", *v) for v in CORNERS) + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    material = {"name": name, "pbrMetallicRoughness": pbr}
    if extensions:
        material["extensions"] = extensions
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
           "extensionsUsed": ["KHR_lights_punctual"] + sorted(extensions), "extensionsRequired": ["KHR_lights_punctual"],
           "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
           "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
           "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-8, 0, -8], "max": [8, 0, 8]},
                         {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
           "materials": [material],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01}}],
           "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 1.2, 1.2], "rotation": [-0.38268343, 0, 0, 0.92387953]},
                     {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": _sun_rotation(to_sun)}]}
    if mapped:
        extra = b"".join(struct.pack("<3f", 0, 1, 0) for _ in CORNERS)
        extra += b"".join(struct.pack("<2f", (x + 8) / 16, (z + 8) / 16) for x, _, z in CORNERS)
        data += extra
        doc["buffers"][0] = {"byteLength": len(data),
                             "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}
        doc["bufferViews"] += [{"buffer": 0, "byteOffset": 60, "byteLength": 48},
                               {"buffer": 0, "byteOffset": 108, "byteLength": 32}]
        doc["accessors"] += [{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"},
                             {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"}]
        doc["meshes"][0]["primitives"][0]["attributes"].update({"NORMAL": 2, "TEXCOORD_0": 3})
    if texel is not None:
        doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(_png(texel)).decode()}]
        doc["samplers"] = [{"magFilter": 9728, "minFilter": 9728}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
    with open(path, "w") as f:
        json.dump(doc, f)


# A mapped plate's tangent frame as glTF defines it: the tangent along dp/du (+x), the bitangent
# up the texture image, −dp/dv (glTF's v runs down the image), so −z.
FRAME = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0))


def exact_image(mi, d, sun, w, h):
    """The exact image (h × w × rgb) of the plate in the Mitsuba scene dict `d` (its files still
    on disk) under the `sun` (gltf_scene's light): at each pixel's centre, the BSDF (with its
    cosine, as Mitsuba's `eval` gives it) from the camera to the sun times the sun's irradiance."""
    import drjit as dr
    import numpy as np

    scene = mi.load_dict(d)
    sensor = scene.sensors()[0]
    idx = dr.arange(mi.UInt32, w * h)
    pos = mi.Point2f((mi.Float(idx % w) + 0.5) / w, (mi.Float(idx // w) + 0.5) / h)
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = scene.ray_intersect(ray)
    to_sun = si.to_local(mi.Vector3f(*(-float(c) for c in sun.direction)))
    value = np.array(si.bsdf().eval(mi.BSDFContext(), si, to_sun, si.is_valid()))
    value = value if value.shape[0] == w * h else value.T  # (pixels, rgb)
    return (value * np.array(sun.intensity)).reshape(h, w, 3)

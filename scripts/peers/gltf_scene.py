"""Reads the glTF scenes smlt renders (the subset smlt reads: triangle meshes with node
transforms, baseColorFactor, emissiveFactor x KHR_materials_emissive_strength, the Phong
exponent in the material's extras, perspective cameras in depth-first scene order,
KHR_lights_punctual lights in smlt's units: candela / 683 W/sr, lux / 683 W/m², glass from
KHR_materials_transmission, _ior and _volume, glTF's metallic-roughness BRDF with KHR_materials_specular
(and KHR_materials_clearcoat's factors),
textures: baseColorTexture, emissiveTexture and metallicRoughnessTexture with their samplers, texCoord
and KHR_texture_transform, the meshes' TEXCOORD_0 and TEXCOORD_1, and their NORMALs, the smooth shading
normals) into plain numpy arrays, for the peers' converters.

Shading normals (glTF 2.0, as smlt reads them from its NORMAL support on): a primitive's NORMAL is a unit vector per vertex,
interpolated over each triangle (barycentrically) and used as the shading normal; it transforms to
world space by the inverse transpose of the node's world matrix (normalised after), as a normal must
under non-uniform and mirroring scales. A primitive without NORMAL is flat: its shading normal is its
geometric normal, (p1 - p0) x (p2 - p0) of its world-space triangle with glTF's front-face (counter-
clockwise) winding, corners 1 and 2 already swapped where the world matrix mirrors (as the positions).

Texture semantics (glTF 2.0, as smlt reads them, shared/src/texture.rs): texture coordinates (0, 0)
are the image's top-left corner, v down; KHR_texture_transform maps them by T · R · S before the
lookup; the sampler's wrapS/wrapT (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) and magFilter (NEAREST,
else bilinear between texel centres) apply, minFilter does not (no mip-maps); colour textures are
sRGB, decoded per texel before filtering; a factor multiplies the filtered texture. `sample` is an
independent numpy implementation of that lookup, for the peers' checks.

KHR_texture_transform's rotation: the extension's GLSL listing builds R with columns (cos, sin) and
(-sin, cos); the extension's own example ("the lower left quadrant ... rotated
clockwise 90°"), its sample model TextureTransformTest and the implementations (Babylon, Blender,
three.js) turn the other way, R's columns (cos, -sin) and (sin, cos) (KhronosGroup/glTF#1563, open),
which smlt follows. `load(..., rotation="example")` (the default) reads it as smlt does;
`rotation="listing"` the other way."""

import base64
import json
import math
import os
from dataclasses import dataclass, field

import numpy as np

PHONG_KEY = "smlt_phong_exponent"
COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT = 10497, 33071, 33648
NEAREST = 9728


@dataclass
class Texture:
    """A material's use of a texture: the encoded image, its sampler, which TEXCOORD_n, and the
    affine map of the coordinates (KHR_texture_transform, a 2 x 3 matrix [M | offset])."""

    image: bytes  # PNG or JPEG, as stored
    mime: str
    nearest: bool  # magFilter NEAREST (else bilinear)
    wrap_s: int  # glTF's enums
    wrap_t: int
    tex_coord: int
    transform: np.ndarray

    def coordinates(self, uv):
        """The lookup's coordinates for mesh coordinates uv (..., 2)."""
        return uv @ self.transform[:, :2].T + self.transform[:, 2]


@dataclass
class Material:
    name: str
    albedo: tuple
    emission: tuple  # radiance (factor x strength)
    phong: float  # 0: Lambertian
    transmission: float = 0.0  # the dielectric's share (x (1 - metallic)); the rest is glTF's BRDF
    ior: float = 1.5
    thin_walled: bool = True  # no KHR_materials_volume (or thicknessFactor 0)
    attenuation: tuple = (0.0, 0.0, 0.0)  # Beer-Lambert coefficient inside a solid, 1/m
    alpha: float = 0.0  # GGX roughness, roughnessFactor^2: the BRDF's, and the glass's (a solid's or a thin wall's)
    metallic: float = 0.0  # glTF's metallicFactor
    specular: float = 0.0  # KHR_materials_specular's specularFactor (1 without it)
    specular_color: tuple = (1.0, 1.0, 1.0)
    base_color_texture: Texture | None = None  # sRGB; x albedo
    emissive_texture: Texture | None = None  # sRGB; x emission
    metallic_roughness_texture: Texture | None = None  # linear; G x roughness, B x metallic
    metallic_factor: float = 1.0  # glTF's own factors (`metallic` above is a share derived from them)
    roughness_factor: float = 1.0
    transmission_factor: float = 0.0
    alpha_mode: str = "OPAQUE"  # glTF's alphaMode: MASK cuts where the opacity < alpha_cutoff; BLEND covers by it
    alpha_cutoff: float = 0.5
    opacity: float = 1.0  # baseColorFactor's alpha (x the base colour texture's alpha)
    clearcoat: float = 0.0  # KHR_materials_clearcoat's clearcoatFactor (0: no coat)
    clearcoat_roughness: float = 0.0  # its clearcoatRoughnessFactor
    sheen_color: tuple = (0.0, 0.0, 0.0)  # KHR_materials_sheen's sheenColorFactor (black: no sheen)
    sheen_roughness: float = 0.0  # its sheenRoughnessFactor

    @property
    def textures(self):
        return [t for t in (self.base_color_texture, self.emissive_texture, self.metallic_roughness_texture) if t]

    @property
    def f0(self):
        """The BRDF's dielectric layer's reflectance at normal incidence."""
        r = ((self.ior - 1.0) / (self.ior + 1.0)) ** 2
        return tuple(min(r * c, 1.0) * self.specular for c in self.specular_color)

    @property
    def lambertian(self):
        """Whether glTF's BRDF is exactly Lambert here (no metal, no dielectric layer)."""
        return self.metallic == 0.0 and self.specular == 0.0

    @property
    def rough_glass(self):
        return self.transmission > 0 and self.alpha >= 1e-3


@dataclass
class Camera:
    position: np.ndarray
    forward: np.ndarray
    up: np.ndarray
    yfov: float  # radians
    aspect: float | None


LUMENS_PER_WATT = 683.0  # Blender's PBR_WATTS_TO_LUMENS, as smlt reads glTF's lights


@dataclass
class Light:
    kind: str  # "point", "spot" or "directional"
    position: np.ndarray
    direction: np.ndarray  # the node's -Z: where a spot points, where a sun's light travels
    intensity: tuple  # W/sr (point, spot) or W/m^2 (directional), rgb
    inner: float  # spot cone angles, radians
    outer: float


@dataclass
class Scene:
    materials: list
    triangles: dict = field(default_factory=dict)  # material index -> (n, 3, 3) world-space vertices
    texcoords: dict = field(default_factory=dict)  # material index -> (n, 3, 2, 2): TEXCOORD_0, _1 (0 if none)
    # material index -> (n, 3, 3) world-space unit shading normals at the triangles' corners, where at
    # least one of the material's primitives has NORMAL (its flat ones get their geometric normal);
    # absent where none has
    normals: dict = field(default_factory=dict)
    cameras: list = field(default_factory=list)
    lights: list = field(default_factory=list)


def _node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.eye(4)
    t[:3, 3] = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    s = np.diag(list(node.get("scale", [1, 1, 1])) + [1.0])
    rot = np.eye(4)
    rot[:3, :3] = r
    return t @ rot @ s


def geometric_normals(tris):
    """The unit geometric normals (n, 3) of world-space triangles (n, 3, 3): glTF's front face,
    counter-clockwise (0 where a triangle is degenerate)."""
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    return np.divide(n, length, out=np.zeros_like(n), where=length > 0)


def texture_transform(offset=(0.0, 0.0), rotation=0.0, scale=(1.0, 1.0), sense="example"):
    """KHR_texture_transform's T · R · S as [M | offset]: R's columns (cos, sin) and (-sin, cos)
    as the extension's GLSL listing (`sense` "listing"), or the opposite turn of its example and
    of the implementations ("example", smlt's reading; see the module doc)."""
    if sense not in ("listing", "example"):
        raise ValueError(f"rotation sense {sense!r}: listing or example")
    c, s = math.cos(rotation), math.sin(rotation) * (1.0 if sense == "listing" else -1.0)
    return np.array([[c * scale[0], -s * scale[1], offset[0]], [s * scale[0], c * scale[1], offset[1]]])


def srgb_to_linear(c):
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _wrap(i, n, mode):
    if mode == CLAMP_TO_EDGE:
        return np.clip(i, 0, n - 1)
    if mode == MIRRORED_REPEAT:
        m = np.mod(i, 2 * n)
        return np.where(m >= n, 2 * n - 1 - m, m)
    return np.mod(i, n)


def sample(texels, tex, uv):
    """glTF's lookup of `texels` ((h, w, c) linear values: sRGB already decoded) with `tex`'s
    sampler at lookup coordinates uv (..., 2), written from the spec (OpenGL's rules: the
    texel under the point, or the four texel centres around it; wrap per axis)."""
    h, w = texels.shape[:2]
    u, v = uv[..., 0], uv[..., 1]
    if tex.wrap_s == CLAMP_TO_EDGE:
        u = np.clip(u, 0.0, 1.0)
    if tex.wrap_t == CLAMP_TO_EDGE:
        v = np.clip(v, 0.0, 1.0)
    x, y = u * w, v * h
    if tex.nearest:
        i, j = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
        return texels[_wrap(j, h, tex.wrap_t), _wrap(i, w, tex.wrap_s)]
    x, y = x - 0.5, y - 0.5
    i, j = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = (x - i)[..., None], (y - j)[..., None]
    i0, i1 = _wrap(i, w, tex.wrap_s), _wrap(i + 1, w, tex.wrap_s)
    j0, j1 = _wrap(j, h, tex.wrap_t), _wrap(j + 1, h, tex.wrap_t)
    return ((1 - fx) * (1 - fy) * texels[j0, i0] + fx * (1 - fy) * texels[j0, i1]
            + (1 - fx) * fy * texels[j1, i0] + fx * fy * texels[j1, i1])


def load(path, rotation="example"):
    doc = json.load(open(path))
    folder = os.path.dirname(os.path.abspath(path))
    buffers = []
    for b in doc.get("buffers", []):
        uri = b["uri"]
        if uri.startswith("data:"):
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            buffers.append(open(os.path.join(folder, uri), "rb").read())

    def accessor(i):
        a = doc["accessors"][i]
        view = doc["bufferViews"][a["bufferView"]]
        dtype = np.dtype(COMPONENT[a["componentType"]])
        width = WIDTH[a["type"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = view.get("byteStride", 0) or dtype.itemsize * width
        raw = buffers[view["buffer"]]
        count = a["count"]
        if stride == dtype.itemsize * width:
            out = np.frombuffer(raw, dtype=dtype, count=count * width, offset=start)
        else:
            rows = [np.frombuffer(raw, dtype=dtype, count=width, offset=start + k * stride) for k in range(count)]
            out = np.concatenate(rows)
        return out.reshape(count, width) if width > 1 else out

    def image_bytes(i):
        img = doc["images"][i]
        if "bufferView" in img:
            view = doc["bufferViews"][img["bufferView"]]
            start = view.get("byteOffset", 0)
            return buffers[view["buffer"]][start:start + view["byteLength"]], img.get("mimeType", "")
        uri = img["uri"]
        if uri.startswith("data:"):
            return base64.b64decode(uri.split(",", 1)[1]), uri[5:].split(";", 1)[0]
        return open(os.path.join(folder, uri), "rb").read(), img.get("mimeType", "")

    def texture(info):
        if info is None:
            return None
        tex = doc["textures"][info["index"]]
        if "source" not in tex:
            return None  # an extension's image (KTX2, WebP): smlt uses the factor alone
        image, mime = image_bytes(tex["source"])
        sampler = doc["samplers"][tex["sampler"]] if "sampler" in tex else {}
        t = info.get("extensions", {}).get("KHR_texture_transform", {})
        return Texture(image, mime, sampler.get("magFilter") == NEAREST, sampler.get("wrapS", REPEAT),
                       sampler.get("wrapT", REPEAT), int(t.get("texCoord", info.get("texCoord", 0))),
                       texture_transform(t.get("offset", (0.0, 0.0)), t.get("rotation", 0.0),
                                         t.get("scale", (1.0, 1.0)), rotation))

    # glTF's default material, as smlt: white, metallic 1, roughness 1
    materials = [Material("default", (1.0, 1.0, 1.0), (0.0, 0.0, 0.0), 0.0, alpha=1.0, metallic=1.0, specular=1.0)]
    for m in doc.get("materials", []):
        base = m.get("pbrMetallicRoughness", {}).get("baseColorFactor", [1, 1, 1, 1])[:3]
        strength = m.get("extensions", {}).get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
        emission = tuple(float(e) * strength for e in m.get("emissiveFactor", [0, 0, 0]))
        phong = float(m.get("extras", {}).get(PHONG_KEY, 0.0))
        ext = m.get("extensions", {})
        transmission = float(ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0))
        ior = float(ext.get("KHR_materials_ior", {}).get("ior", 1.5))
        volume = ext.get("KHR_materials_volume")
        thin = volume is None or volume.get("thicknessFactor", 0.0) <= 0
        attenuation = (0.0, 0.0, 0.0)
        if not thin and math.isfinite(volume.get("attenuationDistance", math.inf)):
            colour = volume.get("attenuationColor", [1, 1, 1])
            attenuation = tuple(-math.log(max(c, 1e-30)) / volume["attenuationDistance"] for c in colour)
        pbr = m.get("pbrMetallicRoughness", {})
        roughness = float(pbr.get("roughnessFactor", 1.0))
        metallic = float(pbr.get("metallicFactor", 1.0))
        spec = ext.get("KHR_materials_specular", {})
        # glTF's mix(dielectric, metal, metallic), the dielectric transmitting: glass t = tr (1 - m),
        # the BRDF share 1 - t metal by m / (1 - t) (as smlt's read.rs)
        t = transmission * (1.0 - metallic)
        metal = min(metallic / (1.0 - t), 1.0) if t < 1.0 else 0.0
        materials.append(Material(m.get("name", ""), tuple(base), emission, phong, t,
                                  ior, thin, attenuation, roughness ** 2, metal,
                                  float(spec.get("specularFactor", 1.0)),
                                  tuple(spec.get("specularColorFactor", [1.0, 1.0, 1.0])),
                                  texture(pbr.get("baseColorTexture")), texture(m.get("emissiveTexture")),
                                  texture(pbr.get("metallicRoughnessTexture")), metallic, roughness,
                                  transmission, m.get("alphaMode", "OPAQUE"), float(m.get("alphaCutoff", 0.5)),
                                  float(pbr.get("baseColorFactor", [1, 1, 1, 1])[3]),
                                  float(ext.get("KHR_materials_clearcoat", {}).get("clearcoatFactor", 0.0)),
                                  float(ext.get("KHR_materials_clearcoat", {}).get("clearcoatRoughnessFactor", 0.0)),
                                  tuple(ext.get("KHR_materials_sheen", {}).get("sheenColorFactor", [0.0, 0.0, 0.0])),
                                  float(ext.get("KHR_materials_sheen", {}).get("sheenRoughnessFactor", 0.0))))
    scene = Scene(materials)
    shading = {}  # material index -> per primitive: ((k, 3, 3) normals or None (flat), its triangles)
    root = doc["scenes"][doc.get("scene", 0)]
    stack = [(n, np.eye(4)) for n in reversed(root["nodes"])]
    while stack:
        index, parent = stack.pop()
        node = doc["nodes"][index]
        world = parent @ _node_matrix(node)
        if "camera" in node:
            cam = doc["cameras"][node["camera"]]
            p = cam["perspective"]
            forward = world[:3, :3] @ np.array([0, 0, -1.0])
            up = world[:3, :3] @ np.array([0, 1.0, 0])
            forward /= np.linalg.norm(forward)
            up = up - forward * up.dot(forward)
            scene.cameras.append(Camera(world[:3, 3].copy(), forward, up / np.linalg.norm(up), p["yfov"], p.get("aspectRatio")))
        light = node.get("extensions", {}).get("KHR_lights_punctual")
        if light is not None:
            spec = doc["extensions"]["KHR_lights_punctual"]["lights"][light["light"]]
            direction = world[:3, :3] @ np.array([0, 0, -1.0])
            scale = spec.get("intensity", 1.0) / LUMENS_PER_WATT
            spot = spec.get("spot", {})
            scene.lights.append(Light(
                spec["type"], world[:3, 3].copy(), direction / np.linalg.norm(direction),
                tuple(float(c) * scale for c in spec.get("color", [1, 1, 1])),
                spot.get("innerConeAngle", 0.0), spot.get("outerConeAngle", math.pi / 4),
            ))
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                pos = accessor(prim["attributes"]["POSITION"]).astype(np.float64)
                pos = (world[:3, :3] @ pos.T).T + world[:3, 3]
                idx = accessor(prim["indices"]).astype(np.int64) if "indices" in prim else np.arange(len(pos))
                tris = pos[idx.reshape(-1, 3)]
                attrs = prim["attributes"]
                uv = np.zeros((len(tris), 3, 2, 2))
                for k in (0, 1):
                    if f"TEXCOORD_{k}" in attrs:
                        # float, or normalised unsigned byte / short (glTF's three encodings)
                        a = doc["accessors"][attrs[f"TEXCOORD_{k}"]]
                        c = accessor(attrs[f"TEXCOORD_{k}"]).astype(np.float64)
                        if a["componentType"] != 5126:
                            c /= np.iinfo(COMPONENT[a["componentType"]]).max
                        uv[:, :, :, k] = c[idx.reshape(-1, 3)]
                normals = None
                if "NORMAL" in attrs and np.linalg.det(world[:3, :3]) != 0:
                    # float (core glTF), or normalised signed byte / short (KHR_mesh_quantization);
                    # to world space by the inverse transpose, normalised after (a singular
                    # matrix has none, its triangles are degenerate: flat, as smlt)
                    a = doc["accessors"][attrs["NORMAL"]]
                    n = accessor(attrs["NORMAL"]).astype(np.float64)
                    if a["componentType"] != 5126:
                        n = np.maximum(n / np.iinfo(COMPONENT[a["componentType"]]).max, -1.0)
                    n = n @ np.linalg.inv(world[:3, :3])  # (M^-T n^T)^T = n M^-1
                    length = np.linalg.norm(n, axis=1, keepdims=True)
                    n = np.divide(n, length, out=np.zeros_like(n), where=length > 0)
                    normals = n[idx.reshape(-1, 3)]
                if np.linalg.det(world[:3, :3]) < 0:
                    tris = tris[:, [0, 2, 1]]
                    uv = uv[:, [0, 2, 1]]
                    if normals is not None:
                        normals = normals[:, [0, 2, 1]]
                m = prim.get("material", -1) + 1
                scene.triangles.setdefault(m, []).append(tris)
                scene.texcoords.setdefault(m, []).append(uv)
                shading.setdefault(m, []).append((normals, tris))
        stack.extend((c, world) for c in reversed(node.get("children", [])))
    scene.triangles = {m: np.concatenate(t) for m, t in scene.triangles.items()}
    scene.texcoords = {m: np.concatenate(t) for m, t in scene.texcoords.items()}
    # a material's flat primitives among smooth ones: their geometric normal at each corner
    scene.normals = {m: np.concatenate([n if n is not None else np.repeat(geometric_normals(t)[:, None], 3, axis=1)
                                        for n, t in prims])
                     for m, prims in shading.items() if any(n is not None for n, _ in prims)}
    return scene


def without_punctual_lights(doc):
    """A glTF document (parsed JSON) with its KHR_lights_punctual lights taken out, in place:
    what the peer checks use where Mitsuba's path tracer cannot render a lamp through glass."""
    for node in doc["nodes"]:
        node.pop("extensions", None)
    doc.pop("extensions", None)
    doc["extensionsUsed"] = [e for e in doc.get("extensionsUsed", []) if e != "KHR_lights_punctual"]
    doc.pop("extensionsRequired", None)
    return doc

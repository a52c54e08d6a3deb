//! Reading glTF 2.0 into a [`TriangleSoup`]: what is read and what is refused is listed in the
//! parent module; here are the loaders, the document walk, materials and cameras.

use std::path::Path;

use glam::{Mat4, Vec3, Vec4, Vec4Swizzles};
use shared::bsdf::Material;
use shared::cutout::{ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE};
use shared::environment::EnvironmentMap;
use shared::normal_map::TriangleTangents;
use shared::normals::TriangleNormals;
use shared::surface::{MaterialTextures, TriangleTexcoords};
use shared::texture::TextureRef;

use super::attributes;
use super::instancing;
use super::morph;
use super::parse::{parse, Parsed};
use super::tangents;
use super::textures::{Source, TextureStore};
use super::{CameraSpec, SceneData, SceneError, TriangleSoup, View};

/// The material-extras key holding the Phong exponent, e.g. `"extras": {"smlt_phong_exponent": 1e5}`.
pub const PHONG_EXPONENT_KEY: &str = "smlt_phong_exponent";

/// The largest world-space coordinate a scene may have (Embree refuses rays beyond 1.8e18; a
/// scene this large has lost every digit a path needs anyway).
pub const MAX_COORDINATE: f32 = 1e15;

impl SceneData {
    /// Loads a glTF (.gltf or .glb) file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        Self::load_with_environment(path, None)
    }

    /// Loads a glTF (.gltf or .glb) file lit by the environment light `environment` too.
    pub fn load_with_environment(
        path: &Path,
        environment: Option<EnvironmentMap>,
    ) -> Result<Self, SceneError> {
        let name = path.display().to_string();
        if path.is_dir() {
            return Err(SceneError::Load { path: name, reason: "is a directory, not a glTF file".into() });
        }
        let bytes = std::fs::read(path)
            .map_err(|e| SceneError::Load { path: name.clone(), reason: e.to_string() })?;
        precheck(&bytes, &name)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let parsed =
            guarded(&name, "the glTF reader", || parse(&bytes, &name, Some(base)))?.map_err(|e| {
                match (&e, missing_resource(path)) {
                    (SceneError::Load { .. }, Some(uri)) => SceneError::Load {
                        path: name.clone(),
                        reason: format!("the file it refers to, '{uri}', does not exist"),
                    },
                    _ => e,
                }
            })?;
        Self::from_parsed(parsed, &name, Some(base), environment)
    }

    /// Loads a glTF document held in memory (a .gltf with data URIs, or a .glb).
    pub fn from_slice(bytes: &[u8], name: &str) -> Result<Self, SceneError> {
        Self::from_slice_with_environment(bytes, name, None)
    }

    /// Loads a glTF document held in memory, lit by the environment light `environment` too.
    pub fn from_slice_with_environment(
        bytes: &[u8],
        name: &str,
        environment: Option<EnvironmentMap>,
    ) -> Result<Self, SceneError> {
        precheck(bytes, name)?;
        let parsed = guarded(name, "the glTF reader", || parse(bytes, name, None))??;
        Self::from_parsed(parsed, name, None, environment)
    }

    /// The scene of a parsed document.
    fn from_parsed(
        parsed: Parsed,
        name: &str,
        base: Option<&Path>,
        environment: Option<EnvironmentMap>,
    ) -> Result<Self, SceneError> {
        check(&parsed.doc, &parsed.buffers, name)?;
        let source = Source {
            doc: &parsed.doc,
            buffers: &parsed.buffers,
            placeholders: &parsed.placeholders,
            base,
            name,
        };
        let mut soup = read_document(&source)?;
        soup.environment = environment;
        let mut scene = Self::from_soup(soup, name)?;
        scene.warnings.extend(parsed.warnings);
        Ok(scene)
    }
}

/// Runs a third-party reader, `reader` (for the message), on `f`, turning a panic inside it
/// into an error: the gltf crate's parsing (seen: its validation indexes `accessors` with a
/// primitive's POSITION before checking it), and the young decoders of compressed data. The
/// panic's own report is held back meanwhile, so that the error is the one line it makes
/// (imports take turns, as the report hook is the process's).
pub(super) fn guarded<T>(name: &str, reader: &str, f: impl FnOnce() -> T) -> Result<T, SceneError> {
    static TURN: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = TURN.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let report = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    std::panic::set_hook(report);
    result.map_err(|panic| {
        let message = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        SceneError::Malformed { path: name.into(), what: format!("{reader} failed on it ({message})") }
    })
}

/// What must hold before the gltf crate reads a document at all (its validation indexes the
/// accessors with a primitive's POSITION unchecked): read from the JSON of a `.gltf` or of a
/// `.glb`'s JSON chunk. A document that is not JSON is left to the gltf crate to refuse.
fn precheck(bytes: &[u8], name: &str) -> Result<(), SceneError> {
    let json: Option<serde_json::Value> = if bytes.starts_with(b"glTF") && bytes.len() >= 20 {
        let length = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
        bytes.get(20..20usize.saturating_add(length)).and_then(|j| serde_json::from_slice(j).ok())
    } else {
        serde_json::from_slice(bytes).ok()
    };
    let Some(json) = json else { return Ok(()) };
    let accessors = json.get("accessors").and_then(|a| a.as_array()).map_or(0, Vec::len) as u64;
    let meshes = json.get("meshes").and_then(|m| m.as_array()).map(Vec::as_slice).unwrap_or(&[]);
    for (m, mesh) in meshes.iter().enumerate() {
        let primitives = mesh.get("primitives").and_then(|p| p.as_array()).map(Vec::as_slice).unwrap_or(&[]);
        for (p, prim) in primitives.iter().enumerate() {
            if let Some(k) = prim.get("attributes").and_then(|a| a.get("POSITION")) {
                // An index written as a float with an integral value is an index (JSON does not
                // tell them apart).
                let index = k
                    .as_u64()
                    .or_else(|| k.as_f64().filter(|f| f.fract() == 0.0 && *f >= 0.0).map(|f| f as u64));
                if !index.is_some_and(|k| k < accessors) {
                    return Err(SceneError::Malformed {
                        path: name.into(),
                        what: format!(
                            "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {k} does not exist"
                        ),
                    });
                }
            }
        }
    }
    Ok(())
}

/// The structural checks of `super::validate` on a loaded document.
fn check(doc: &gltf::Document, buffers: &[gltf::buffer::Data], name: &str) -> Result<(), SceneError> {
    let json = serde_json::to_value(doc.as_json())
        .map_err(|e| SceneError::Load { path: name.into(), reason: e.to_string() })?;
    let lengths: Vec<usize> = buffers.iter().map(|b| b.0.len()).collect();
    super::validate::validate(&json, &lengths)
        .map_err(|what| SceneError::Malformed { path: name.into(), what })
}

/// The first buffer or image URI of the glTF at `path` (a readable file) whose file is
/// missing, to name it in the error.
fn missing_resource(path: &Path) -> Option<String> {
    let gltf = gltf::Gltf::open(path).ok()?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let buffers = gltf.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(uri) => Some(uri.to_string()),
        gltf::buffer::Source::Bin => None,
    });
    // Images from the JSON: the crate's accessor panics on an image without a source.
    let images = gltf.as_json().images.iter().filter_map(|i| i.uri.clone());
    buffers.chain(images).find(|uri| {
        let file = urlencoding::decode(uri).map(|p| dir.join(p.as_ref())).unwrap_or_else(|_| dir.join(uri));
        !uri.starts_with("data:") && !file.exists()
    })
}

/// A hash of a glTF file and every external buffer and image it refers to (what a cache or a
/// part file must change with: a changed `.bin` or texture changes the scene).
pub fn files_hash(path: &Path) -> Result<String, SceneError> {
    let fail = |reason: String| SceneError::Load { path: path.display().to_string(), reason };
    let mut bytes = std::fs::read(path).map_err(|e| fail(e.to_string()))?;
    if let Ok(gltf) = gltf::Gltf::from_slice(&bytes) {
        let dir = path.parent().unwrap_or(Path::new("."));
        let file =
            |uri: &str| urlencoding::decode(uri).map_or_else(|_| dir.join(uri), |p| dir.join(p.as_ref()));
        let buffers: Vec<String> = gltf
            .buffers()
            .filter_map(|b| match b.source() {
                gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => Some(uri.to_string()),
                _ => None,
            })
            .collect();
        for uri in buffers {
            bytes.extend(std::fs::read(file(&uri)).map_err(|e| fail(format!("{uri}: {e}")))?);
        }
        // Images from the JSON (the crate's accessor panics on an image without a source); a
        // missing one is the loader's to report, or to leave out if no material reads it.
        for uri in
            gltf.as_json().images.iter().filter_map(|i| i.uri.as_deref()).filter(|u| !u.starts_with("data:"))
        {
            bytes.extend(std::fs::read(file(uri)).unwrap_or_else(|_| uri.as_bytes().to_vec()));
        }
    }
    Ok(crate::hash::content_hash(&bytes))
}

/// One warning for each kind of texture that is read but not used, naming the materials that
/// have one (an asset's every material often has both: said once, not once a material).
fn ignored_textures(doc: &gltf::Document) -> Vec<String> {
    let named = |has: &dyn Fn(&gltf::Material) -> bool| -> Vec<String> {
        doc.materials()
            .filter(|m| has(m))
            .map(|m| {
                m.name()
                    .map(|n| format!("'{n}'"))
                    .unwrap_or_else(|| format!("materials[{}]", m.index().unwrap_or(0)))
            })
            .collect()
    };
    let warning = |texture: &str, materials: Vec<String>, why: &str| {
        (!materials.is_empty()).then(|| {
            let on = match materials.len() {
                1 => format!("material {}", materials[0]),
                n if n <= 4 => format!("{n} materials ({})", materials.join(", ")),
                n => format!("{n} materials ({}, …)", materials[..3].join(", ")),
            };
            format!("{texture} is ignored on {on}: {why}")
        })
    };
    [warning(
        "occlusionTexture",
        named(&|m| m.occlusion_texture().is_some()),
        "a path tracer computes occlusion; the texture is an approximation of it",
    )]
    .into_iter()
    .flatten()
    .collect()
}

/// A material, and its textures where it has any (`Material::textures` is set by the caller).
fn read_material(
    m: &gltf::Material,
    store: &mut TextureStore,
    source: &Source,
    warnings: &mut Vec<String>,
) -> Result<(Material, Option<MaterialTextures>), SceneError> {
    let name = source.name;
    let label =
        m.name().map(|n| format!("material '{n}'")).unwrap_or_else(|| format!("material {:?}", m.index()));
    let pbr = m.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    let at = m.index().map(|i| format!("materials[{i}]")).unwrap_or_else(|| label.clone());
    let (normal, normal_scale) = match m.normal_texture() {
        Some(n) => store.normal_reference(source, &n, &format!("{at}.normalTexture"), warnings)?,
        None => (TextureRef::NONE, 1.0),
    };
    let mut slot = |info: Option<gltf::texture::Info>, path: &str, warnings: &mut Vec<String>| match info {
        Some(info) => store.reference(source, &info, &format!("{at}.{path}"), warnings),
        None => Ok(TextureRef::NONE),
    };
    let textures = MaterialTextures {
        base_color: slot(pbr.base_color_texture(), "pbrMetallicRoughness.baseColorTexture", warnings)?,
        metallic_roughness: slot(
            pbr.metallic_roughness_texture(),
            "pbrMetallicRoughness.metallicRoughnessTexture",
            warnings,
        )?,
        emissive: slot(m.emissive_texture(), "emissiveTexture", warnings)?,
        normal,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        transmission: m.transmission().map_or(0.0, |t| t.transmission_factor()),
        alpha_mode: ALPHA_OPAQUE,
        alpha_cutoff: 0.5,
        alpha: base[3],
        normal_scale,
        // The clear coat's, from `read_clearcoat` below.
        ..MaterialTextures::default()
    };
    let strength = m.emissive_strength().unwrap_or(1.0);
    let e = m.emissive_factor();
    let textures =
        read_alpha(m, textures, e[0].max(e[1]).max(e[2]) * strength > 0.0, &label, &at, warnings, name)?;
    let mut phong = 0.0f32;
    if let Some(raw) = m.extras() {
        let value: serde_json::Value =
            serde_json::from_str(raw.get()).map_err(|err| SceneError::Unsupported {
                path: name.into(),
                what: format!("{label}: extras are not JSON: {err}"),
            })?;
        if let Some(v) = value.get(PHONG_EXPONENT_KEY) {
            phong = v.as_f64().filter(|x| x.is_finite() && *x >= 0.0 && *x <= 1e6).ok_or_else(|| {
                SceneError::Unsupported {
                    path: name.into(),
                    what: format!("{label}: {PHONG_EXPONENT_KEY} must be a number in [0, 1e6], got {v}"),
                }
            })? as f32;
        }
    }
    let glass = read_glass(m, &label, warnings, name)?;
    let coat = read_clearcoat(m, store, source, &at, warnings)?;
    if coat.factor > 0.0 && e[0].max(e[1]).max(e[2]) * strength > 0.0 {
        warnings.push(format!(
            "{label}: its emission is not darkened by its clear coat (the extension darkens it)"
        ));
    }
    let textures = MaterialTextures {
        clearcoat: coat.texture,
        clearcoat_roughness: coat.roughness_texture,
        clearcoat_factor: coat.factor,
        clearcoat_roughness_factor: coat.roughness,
        clearcoat_normal: coat.normal,
        clearcoat_normal_scale: coat.normal_scale,
        ..textures
    };
    let textured = textures.slots().iter().any(TextureRef::is_some) || textures.alpha_mode != ALPHA_OPAQUE;
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}.{what}") };
    let unit = |x: f32| (0.0..=1.0).contains(&x);
    let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
    if !unit(metallic) {
        return Err(malformed(format!(
            "pbrMetallicRoughness.metallicFactor: {metallic}: must lie in [0, 1]"
        )));
    }
    if !unit(roughness) {
        return Err(malformed(format!(
            "pbrMetallicRoughness.roughnessFactor: {roughness}: must lie in [0, 1]"
        )));
    }
    let (mut specular, mut specular_color) = (1.0, [1.0; 3]);
    if let Some(ext) = m.specular() {
        specular = ext.specular_factor();
        specular_color = ext.specular_color_factor();
        if !unit(specular) {
            return Err(malformed(format!(
                "extensions.KHR_materials_specular.specularFactor: {specular}: must lie in [0, 1]"
            )));
        }
        if !specular_color.iter().all(|c| c.is_finite() && *c >= 0.0) {
            return Err(malformed(format!(
                "extensions.KHR_materials_specular.specularColorFactor: {specular_color:?}: each component must be finite and ≥ 0"
            )));
        }
        if ext.specular_texture().is_some() || ext.specular_color_texture().is_some() {
            warnings.push(format!(
                "{label}: KHR_materials_specular's textures are ignored (its factors are used)"
            ));
        }
    }
    let material = Material {
        albedo: [base[0], base[1], base[2]],
        phong_exponent: phong,
        emission: [e[0] * strength, e[1] * strength, e[2] * strength],
        alpha: roughness * roughness,
        specular,
        specular_color,
        clearcoat: coat.factor,
        clearcoat_alpha: coat.roughness * coat.roughness,
        ..glass
    }
    .with_metallic(metallic, glass.transmission);
    Ok((material, textured.then_some(textures)))
}

/// A material's `KHR_materials_clearcoat` (its numbers checked by `super::validate`).
struct Clearcoat {
    /// clearcoatFactor (0: no coat).
    factor: f32,
    /// clearcoatRoughnessFactor.
    roughness: f32,
    texture: TextureRef,
    roughness_texture: TextureRef,
    normal: TextureRef,
    /// clearcoatNormalTexture's scale.
    normal_scale: f32,
}

/// The clear coat of `m` (`shared::clearcoat`): its factors and the textures they multiply, and
/// its normal texture (none where the factor is 0: the layer is off).
fn read_clearcoat(
    m: &gltf::Material,
    store: &mut TextureStore,
    source: &Source,
    at: &str,
    warnings: &mut Vec<String>,
) -> Result<Clearcoat, SceneError> {
    let mut coat = Clearcoat {
        factor: 0.0,
        roughness: 0.0,
        texture: TextureRef::NONE,
        roughness_texture: TextureRef::NONE,
        normal: TextureRef::NONE,
        normal_scale: 1.0,
    };
    let Some(ext) = m.extension_value("KHR_materials_clearcoat") else {
        return Ok(coat);
    };
    let factor = |key: &str| ext.get(key).and_then(serde_json::Value::as_f64).unwrap_or(0.0) as f32;
    (coat.factor, coat.roughness) = (factor("clearcoatFactor"), factor("clearcoatRoughnessFactor"));
    if coat.factor == 0.0 {
        return Ok(coat);
    }
    let at = format!("{at}.extensions.KHR_materials_clearcoat");
    let mut slot = |key: &str, warnings: &mut Vec<String>| match ext.get(key) {
        Some(info) => store.json_reference(source, info, &format!("{at}.{key}"), warnings),
        None => Ok(TextureRef::NONE),
    };
    coat.texture = slot("clearcoatTexture", warnings)?;
    coat.roughness_texture = slot("clearcoatRoughnessTexture", warnings)?;
    coat.normal = slot("clearcoatNormalTexture", warnings)?;
    if let Some(scale) = ext.get("clearcoatNormalTexture").and_then(|t| t.get("scale")) {
        coat.normal_scale = scale.as_f64().filter(|s| s.is_finite()).ok_or_else(|| SceneError::Malformed {
            path: source.name.into(),
            what: format!("{at}.clearcoatNormalTexture.scale: {scale} is not a finite number"),
        })? as f32;
    }
    Ok(coat)
}

/// The cut-out of a material (`shared::cutout`): its `alphaMode` and `alphaCutoff` into
/// `textures` (whose `alpha` holds `baseColorFactor`'s). An emitter stays opaque, with a
/// warning: light sampling picks points over an emitter's whole surface.
fn read_alpha(
    m: &gltf::Material,
    mut textures: MaterialTextures,
    emissive: bool,
    label: &str,
    at: &str,
    warnings: &mut Vec<String>,
    name: &str,
) -> Result<MaterialTextures, SceneError> {
    let mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => return Ok(textures),
        gltf::material::AlphaMode::Mask => ALPHA_MASK,
        gltf::material::AlphaMode::Blend => ALPHA_BLEND,
    };
    let alpha = textures.alpha;
    if !(0.0..=1.0).contains(&alpha) {
        return Err(SceneError::Malformed {
            path: name.into(),
            what: format!("{at}.pbrMetallicRoughness.baseColorFactor: alpha {alpha}: must lie in [0, 1]"),
        });
    }
    let cutoff = m.alpha_cutoff().unwrap_or(0.5);
    if !(cutoff.is_finite() && cutoff >= 0.0) {
        return Err(SceneError::Malformed {
            path: name.into(),
            what: format!("{at}.alphaCutoff: {cutoff}: must be a finite number ≥ 0"),
        });
    }
    if emissive {
        warnings.push(format!(
            "{label}: alphaMode {:?} on an emitter is not modelled: it renders opaque",
            m.alpha_mode()
        ));
        return Ok(textures);
    }
    textures.alpha_mode = mode;
    textures.alpha_cutoff = cutoff;
    Ok(textures)
}

/// The dielectric of a material (`KHR_materials_transmission`, `_ior`, `_volume`) as the
/// spec defines it: the `transmissionFactor` share of the material is a smooth dielectric of
/// index `ior`, thin-walled without `KHR_materials_volume` (or with thicknessFactor 0), the
/// boundary of a solid with it, attenuating by Beer–Lambert with −ln(attenuationColor) /
/// attenuationDistance. A thin wall's rough transmission is rendered smooth, with a warning.
fn read_glass(
    m: &gltf::Material,
    label: &str,
    warnings: &mut Vec<String>,
    name: &str,
) -> Result<Material, SceneError> {
    let at = m.index().map(|i| format!("materials[{i}].extensions")).unwrap_or_else(|| label.to_string());
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}.{what}") };
    let mut glass = Material { ior: 1.5, thin_walled: 1, ..Default::default() };
    if let Some(ior) = m.ior() {
        if ior == 0.0 {
            // The spec's special value: the Fresnel factor is 1 at every angle.
            return Err(SceneError::Unsupported {
                path: name.into(),
                what: format!("{at}.KHR_materials_ior.ior: 0 (a Fresnel factor of 1) is not modelled"),
            });
        }
        if !(ior.is_finite() && ior >= 1.0) {
            return Err(malformed(format!("KHR_materials_ior.ior: {ior}: must be a finite number ≥ 1")));
        }
        glass.ior = ior;
    }
    let Some(transmission) = m.transmission() else { return Ok(glass) };
    let factor = transmission.transmission_factor();
    if !(0.0..=1.0).contains(&factor) {
        return Err(malformed(format!(
            "KHR_materials_transmission.transmissionFactor: {factor}: must lie in [0, 1]"
        )));
    }
    glass.transmission = factor;
    if transmission.transmission_texture().is_some() {
        warnings.push(format!("{label}: transmissionTexture is ignored (its factor is used)"));
    }
    if let Some(volume) = m.volume() {
        let distance = volume.attenuation_distance();
        if !(distance > 0.0) {
            return Err(malformed(format!(
                "KHR_materials_volume.attenuationDistance: {distance}: must be > 0"
            )));
        }
        let color = volume.attenuation_color();
        if !color.iter().all(|c| (0.0..=1.0).contains(c)) {
            return Err(malformed(format!(
                "KHR_materials_volume.attenuationColor: {color:?}: each component must lie in [0, 1]"
            )));
        }
        if volume.thickness_factor() > 0.0 {
            glass.thin_walled = 0;
            if distance.is_finite() {
                glass.attenuation = color.map(|c| -c.max(1e-30).ln() / distance);
            }
        }
    }
    // A solid's interface is as rough as the material (GGX, α = roughness², set by the
    // caller); a thin wall's rough passage is not modelled.
    let roughness = m.pbr_metallic_roughness().roughness_factor();
    if factor > 0.0 && roughness > 0.0 && glass.thin_walled != 0 {
        warnings.push(format!("{label}: a thin wall's rough transmission is rendered smooth"));
    }
    Ok(glass)
}

/// Reads the triangles, materials and camera of a glTF document.
pub fn read_document(source: &Source) -> Result<TriangleSoup, SceneError> {
    let (doc, buffers, placeholders, name) = (source.doc, source.buffers, source.placeholders, source.name);
    let mut soup = TriangleSoup::default();
    for ext in doc.extensions_used() {
        if ![
            "KHR_materials_emissive_strength",
            "KHR_lights_punctual",
            "KHR_materials_transmission",
            "KHR_materials_ior",
            "KHR_materials_volume",
            "KHR_materials_specular",
            "KHR_texture_transform",
        ]
        .contains(&ext)
            && !super::parse::READ_BY_SMLT.contains(&ext)
        {
            soup.warnings.push(format!("extension {ext} is ignored"));
        }
    }
    // Material 0 is glTF's default material (the spec's: white, metallicFactor 1,
    // roughnessFactor 1); document materials follow.
    soup.materials.push(Material {
        albedo: [1.0; 3],
        ior: 1.5,
        alpha: 1.0,
        metallic: 1.0,
        specular: 1.0,
        specular_color: [1.0; 3],
        ..Default::default()
    });
    // Entry 0 of the material textures is never used (`Material::textures` 0: none).
    soup.material_textures.push(MaterialTextures::default());
    let mut store = TextureStore::default();
    soup.warnings.extend(ignored_textures(doc));
    for m in doc.materials() {
        let (mut mat, textures) = read_material(&m, &mut store, source, &mut soup.warnings)?;
        if let Some(t) = textures {
            mat.textures = soup.material_textures.len() as u32;
            soup.material_textures.push(t);
        }
        soup.materials.push(mat);
    }
    soup.textures = store.textures;
    soup.texels = store.texels;
    // Texture coordinates are kept for every triangle where any material reads them, none
    // otherwise.
    let any_textures = soup.material_textures.len() > 1;
    let scene =
        doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| SceneError::Empty(name.into()))?;
    // glTF's node hierarchy is a set of disjoint trees: a node reached twice has two parents or
    // is its own ancestor, and a walk through a cycle would never end.
    let mut reached = vec![false; doc.nodes().len()];
    // Skinned mesh nodes, drawn unposed (skins are not applied), named once in a warning.
    let mut skinned = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, Option<usize>)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, None)).collect();
    stack.reverse();
    while let Some((node, parent, parent_index)) = stack.pop() {
        if std::mem::replace(&mut reached[node.index()], true) {
            let via = parent_index.map(|p| format!(" (again as a child of node {p})")).unwrap_or_default();
            return Err(SceneError::Unsupported {
                path: name.into(),
                what: format!(
                    "the node graph is not a tree: node {} is reached twice{via}; a cycle or a shared node",
                    node.index()
                ),
            });
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(light) = node.light() {
            let light = super::lights::read_light(&light, node.index(), world, name, &mut soup.warnings)?;
            soup.punctual.push(light);
        }
        if let Some(cam) = node.camera() {
            {
                match cam.projection() {
                    gltf::camera::Projection::Perspective(p) => {
                        let forward = (world * glam::Vec4::new(0.0, 0.0, -1.0, 0.0)).xyz().normalize();
                        let up = (world * glam::Vec4::new(0.0, 1.0, 0.0, 0.0)).xyz().normalize();
                        let position = (world * glam::Vec4::W).xyz();
                        if !(position.abs().max_element() <= MAX_COORDINATE
                            && forward.is_finite()
                            && up.is_finite())
                        {
                            return Err(SceneError::Malformed {
                                path: name.into(),
                                what: format!(
                                    "nodes[{}]: the camera's world transform is degenerate or beyond ±{MAX_COORDINATE:e}",
                                    node.index()
                                ),
                            });
                        }
                        if !(p.yfov() < std::f32::consts::PI) {
                            return Err(SceneError::Unsupported {
                                path: name.into(),
                                what: format!(
                                    "cameras[{}].perspective.yfov: {} rad: a pinhole camera sees less than π",
                                    cam.index(),
                                    p.yfov()
                                ),
                            });
                        }
                        soup.cameras.push(View::Perspective(CameraSpec {
                            position,
                            forward,
                            up: (up - forward * up.dot(forward)).normalize(),
                            yfov: p.yfov(),
                            aspect: p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0),
                        }));
                    }
                    gltf::camera::Projection::Orthographic(_) => {
                        let view = soup.cameras.len() + 1;
                        soup.warnings.push(format!(
                            "cameras[{}] (view {view}, on nodes[{}]) is orthographic: smlt renders perspective \
                             cameras, so it is not rendered (--view {view} is refused)",
                            cam.index(),
                            node.index()
                        ));
                        soup.cameras.push(View::Orthographic { camera: cam.index() });
                    }
                }
            }
        }
        if let Some(mesh) = node.mesh() {
            if node.skin().is_some() {
                skinned.push(node.index());
            }
            // Drawn once for each instance (`instancing`), at the node's world matrix times
            // the instance's; a node without instances has one, the identity.
            let node_world = world;
            let get = |b: gltf::Buffer| buffers.get(b.index()).map(|d| &d.0[..]);
            for instance in instancing::transforms(&node, doc, get, name)? {
                let world = node_world * instance;
                for prim in mesh.primitives() {
                    if prim.mode() != gltf::mesh::Mode::Triangles {
                        return Err(SceneError::Unsupported {
                            path: name.into(),
                            what: format!(
                                "primitive mode {:?} in mesh {} (only TRIANGLES)",
                                prim.mode(),
                                mesh.index()
                            ),
                        });
                    }
                    // The indices through the gltf crate's reader, vertex attributes through
                    // `attributes`, which reads every type the spec allows them.
                    let get = |b: gltf::Buffer| buffers.get(b.index()).map(|d| &d.0[..]);
                    let reader = prim.reader(get);
                    let at = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
                    let malformed = |what: String| SceneError::Malformed { path: name.into(), what };
                    for accessor in prim.attributes().map(|(_, a)| a).chain(prim.indices()) {
                        let views = accessor.view().into_iter().chain(
                            accessor
                                .sparse()
                                .into_iter()
                                .flat_map(|s| [s.indices().view(), s.values().view()]),
                        );
                        if let Some(b) = views.map(|v| v.buffer().index()).find(|b| placeholders.contains(b))
                        {
                            return Err(SceneError::Unsupported {
                            path: name.into(),
                            what: format!(
                                "{at} reads buffers[{b}], whose data is not in the file (no uri, no BIN chunk)"
                            ),
                        });
                        }
                    }
                    let Some(positions_accessor) = prim.get(&gltf::Semantic::Positions) else {
                        soup.warnings.push(format!("{at} has no POSITION: skipped, as the spec says"));
                        continue;
                    };
                    let mut local: Vec<[f32; 3]> = match attributes::read(&positions_accessor, get) {
                        Some(p) => p,
                        // No view and no sparse values: zeros, as the spec says.
                        None if positions_accessor.view().is_none() => {
                            vec![[0.0; 3]; positions_accessor.count()]
                        }
                        None => return Err(malformed(format!("{at}: its POSITION accessor cannot be read"))),
                    };
                    let weights = morph::weights(&node, &mesh);
                    morph::displace(get, &prim, gltf::Semantic::Positions, weights, &mut local, (&at, name))?;
                    if morph::moves_tangents(&prim, weights) {
                        soup.warnings.push(format!(
                        "{at}: its morph targets' TANGENT displacements are not applied (POSITION and NORMAL are)"
                    ));
                    }
                    if let Some(i) = local.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
                        return Err(malformed(format!("{at}: POSITION {i} is not finite: {:?}", local[i])));
                    }
                    let positions: Vec<Vec3> =
                        local.iter().map(|p| world.transform_point3(Vec3::from_array(*p))).collect();
                    if let Some(i) = positions.iter().position(|p| !(p.abs().max_element() <= MAX_COORDINATE))
                    {
                        return Err(malformed(format!(
                        "{at}: POSITION {i} lies at {} after the node transforms, beyond ±{MAX_COORDINATE:e}",
                        positions[i]
                    )));
                    }
                    let indices: Vec<u32> = match (reader.read_indices(), prim.indices()) {
                        (Some(i), _) => i.into_u32().collect(),
                        // An index accessor without a view or sparse values: zeros, as the spec says.
                        (None, Some(a)) => vec![0; a.count()],
                        (None, None) => (0..positions.len() as u32).collect(),
                    };
                    let material = prim.material().index().map(|i| i as u32 + 1).unwrap_or(0);
                    let textures = soup.materials[material as usize].textures;
                    let texcoords = read_texcoords(get, &prim, &soup, material, &at, positions.len(), name)?;
                    let local_normals = read_normals(get, &prim, weights, &at, positions.len(), name)?;
                    // Normals transform by the inverse transpose of the node's matrix; a matrix
                    // without an inverse leaves degenerate triangles, which are flat.
                    let to_world = glam::Mat3::from_mat4(world).inverse().transpose();
                    let normals: Option<Vec<Vec3>> = local_normals
                        .as_ref()
                        .filter(|_| to_world.is_finite())
                        .map(|n| n.iter().map(|n| (to_world * *n).normalize_or_zero()).collect());
                    let (triples, rest) = indices.as_chunks::<3>();
                    // Every corner a vertex, before anything reads the corners.
                    if let Some(&i) = triples.as_flattened().iter().find(|&&i| i as usize >= positions.len())
                    {
                        return Err(malformed(format!(
                            "{at}.indices: index {i} is not below the {} vertices",
                            positions.len()
                        )));
                    }
                    // A normal texture's vertex tangents, each triangle's corners in the mesh's space:
                    // in the coordinates of the normal texture, else of the coat's (as
                    // `shared::surface::normals_at` takes them).
                    let normal_texture = (textures != 0)
                        .then(|| {
                            let t = &soup.material_textures[textures as usize];
                            if t.normal.is_some() {
                                t.normal
                            } else {
                                t.clearcoat_normal
                            }
                        })
                        .filter(TextureRef::is_some);
                    let tangents = match (normal_texture, &local_normals, &texcoords) {
                        (Some(r), Some(normals), Some(sets)) => {
                            let mesh =
                                tangents::MeshData { positions: &local, normals, sets, triangles: triples };
                            Some(tangents::corner_tangents(
                                get,
                                &prim,
                                r,
                                &mesh,
                                (&at, name),
                                &mut soup.warnings,
                            )?)
                        }
                        // A mesh without normals is flat: the spec says to ignore its TANGENT, and
                        // each triangle keeps its own frame.
                        _ => None,
                    };
                    if !rest.is_empty() {
                        soup.warnings.push(format!(
                        "{at}: {} indices (or vertices) are no multiple of 3: the last {} form no triangle",
                        indices.len(),
                        rest.len()
                    ));
                    }
                    for (j, tri) in triples.iter().enumerate() {
                        let mut v = [Vec3::ZERO; 3];
                        for (k, &i) in tri.iter().enumerate() {
                            v[k] = *positions.get(i as usize).ok_or_else(|| {
                                malformed(format!(
                                    "{at}.indices: index {i} is not below the {} vertices",
                                    positions.len()
                                ))
                            })?;
                        }
                        let mut corners = [tri[0], tri[1], tri[2]];
                        let mut order = [0, 1, 2];
                        // A mirroring transform flips the winding; keep the normal's sense.
                        if world.determinant() < 0.0 {
                            v.swap(1, 2);
                            corners.swap(1, 2);
                            order.swap(1, 2);
                        }
                        soup.triangles.push(v);
                        soup.material_of.push(material);
                        if let Some(normals) = &normals {
                            // Only a triangle whose normals bend is stored (the rest are flat).
                            let ng = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
                            let ns = corners.map(|i| normals[i as usize]);
                            if ns.iter().any(|n| !(n.dot(ng) > 1.0 - 1e-6)) {
                                soup.normals.resize(soup.triangles.len() - 1, TriangleNormals::default());
                                let n = [ns[0].to_array(), ns[1].to_array(), ns[2].to_array()];
                                soup.normals
                                    .push(TriangleNormals { n: *n.as_flattened().as_array().expect("nine") });
                            }
                        }
                        if let Some(tangents) = &tangents {
                            let t = order.map(|k| tangents::to_world(world, tangents[j][k]));
                            if t.iter().any(|t| *t != Vec4::ZERO) {
                                soup.tangents.resize(soup.triangles.len() - 1, TriangleTangents::default());
                                let t = [t[0].to_array(), t[1].to_array(), t[2].to_array()];
                                soup.tangents.push(TriangleTangents {
                                    t: *t.as_flattened().as_array().expect("twelve"),
                                });
                            }
                        }
                        if let Some(sets) = &texcoords {
                            let mut uv = [0.0f32; 12];
                            for (set, coords) in sets.iter().enumerate() {
                                for (k, &i) in corners.iter().enumerate() {
                                    let c = coords.get(i as usize).copied().unwrap_or_default();
                                    uv[6 * set + 2 * k..6 * set + 2 * k + 2].copy_from_slice(&c);
                                }
                            }
                            soup.texcoords.push(TriangleTexcoords { uv });
                        } else if any_textures {
                            soup.texcoords.push(TriangleTexcoords::default());
                        }
                    }
                }
            }
        }
        let children: Vec<_> = node.children().map(|c| (c, world, Some(node.index()))).collect();
        stack.extend(children.into_iter().rev());
    }
    if !skinned.is_empty() {
        let named: Vec<String> = skinned.iter().take(3).map(|n| format!("nodes[{n}]")).collect();
        let more = if skinned.len() > 3 { ", …" } else { "" };
        soup.warnings.push(format!(
            "{} skinned mesh node(s) ({}{more}) drawn unposed where the node places them: skins are not applied",
            skinned.len(),
            named.join(", ")
        ));
    }
    Ok(soup)
}

/// A primitive's vertex normals in the mesh's space (of length near 1, as read), or None where
/// it has none (the mesh is flat, as the spec says).
fn read_normals<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    weights: &[f32],
    at: &str,
    vertices: usize,
    name: &str,
) -> Result<Option<Vec<Vec3>>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let Some(accessor) = prim.get(&gltf::Semantic::Normals) else {
        return Ok(None);
    };
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    let local: Vec<[f32; 3]> = match attributes::read(&accessor, get.clone()) {
        Some(n) => n,
        // No view and no sparse values: zeros, which no normal can be.
        None if accessor.view().is_none() => vec![[0.0; 3]; accessor.count()],
        None => return Err(malformed("its NORMAL accessor cannot be read".into())),
    };
    if local.len() < vertices {
        return Err(malformed(format!("NORMAL has {} values for {vertices} vertices", local.len())));
    }
    let mut normals = Vec::with_capacity(local.len());
    for (i, n) in local.iter().enumerate() {
        let n = Vec3::from_array(*n);
        // The spec asks for unit normals; a slightly longer or shorter one is normalised.
        if !(n.is_finite() && n.length() > 0.5) {
            return Err(malformed(format!("NORMAL {i} is not a unit vector: {n}")));
        }
        normals.push(n);
    }
    if weights.iter().any(|&w| w != 0.0) {
        // Displaced by the morph targets, then normalised again (the spec's rule).
        let mut displaced: Vec<[f32; 3]> = normals.iter().map(|n| n.to_array()).collect();
        morph::displace(get, prim, gltf::Semantic::Normals, weights, &mut displaced, (at, name))?;
        for (i, (n, d)) in normals.iter_mut().zip(&displaced).enumerate() {
            *n = Vec3::from_array(*d).normalize_or_zero();
            if *n == Vec3::ZERO {
                return Err(malformed(format!("NORMAL {i}: its morph targets cancel it")));
            }
        }
    }
    Ok(Some(normals))
}

/// The texture coordinates a primitive's textured material reads (`TEXCOORD_0` and, where a
/// texture of the material uses it, `TEXCOORD_1`; a set it does not use is zeros), or None for
/// a material without textures. A set the material uses and the primitive lacks is refused, as
/// the Khronos validator does.
fn read_texcoords<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    soup: &TriangleSoup,
    material: u32,
    at: &str,
    vertices: usize,
    name: &str,
) -> Result<Option<[Vec<[f32; 2]>; 2]>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let textures = soup.materials[material as usize].textures;
    if textures == 0 {
        return Ok(None);
    }
    let t = &soup.material_textures[textures as usize];
    let mut sets = [Vec::new(), Vec::new()];
    for (set, coords) in sets.iter_mut().enumerate() {
        let uses = t.slots().iter().any(|r| r.is_some() && r.tex_coord == set as u32);
        if !uses {
            continue;
        }
        let Some(accessor) = prim.get(&gltf::Semantic::TexCoords(set as u32)) else {
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!(
                    "{at}: its material (materials[{}]) reads TEXCOORD_{set}, which the primitive does not have",
                    material - 1
                ),
            });
        };
        *coords = match attributes::read(&accessor, get.clone()) {
            Some(c) => c,
            // No view and no sparse values: zeros, as the spec says.
            None if accessor.view().is_none() => vec![[0.0; 2]; accessor.count()],
            None => {
                return Err(SceneError::Malformed {
                    path: name.into(),
                    what: format!("{at}: its TEXCOORD_{set} accessor cannot be read"),
                })
            }
        };
        if coords.len() < vertices {
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!("{at}: TEXCOORD_{set} has {} values for {vertices} vertices", coords.len()),
            });
        }
    }
    Ok(Some(sets))
}

//! Reading glTF 2.0 into a [`TriangleSoup`]: what is read and what is refused is listed in the
//! parent module; here are the loaders, the document walk, materials and cameras.

use std::path::Path;

use glam::{Mat4, Vec4Swizzles};
use shared::bsdf::Material;
use shared::cutout::{ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE};
use shared::environment::EnvironmentMap;
use shared::surface::MaterialTextures;
use shared::texture::TextureRef;

use super::colors::ColouredMaterials;
use super::instancing;
use super::morph;
use super::parse::{parse, Parsed};
use super::primitive::{self, Placement};
use super::skin;
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

/// A material, its textures entry, and whether it keeps one (it has textures, a cut-out or
/// anisotropy; `Material::textures` is set by the caller).
fn read_material(
    m: &gltf::Material,
    store: &mut TextureStore,
    source: &Source,
    warnings: &mut Vec<String>,
) -> Result<(Material, MaterialTextures, bool), SceneError> {
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
        transmission_factor: m.transmission().map_or(0.0, |t| t.transmission_factor()),
        // Not read where the factor is 0: it multiplies the factor.
        transmission: slot(
            m.transmission().filter(|t| t.transmission_factor() > 0.0).and_then(|t| t.transmission_texture()),
            "extensions.KHR_materials_transmission.transmissionTexture",
            warnings,
        )?,
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
    let glass = read_glass(m, &label, name)?;
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
    let (anisotropy, anisotropy_texture) = read_anisotropy(m, store, source, &at, warnings)?;
    let sheen = read_sheen(m, store, source, &at, warnings)?;
    let mut textures = MaterialTextures {
        anisotropic: u32::from(anisotropy != [0.0; 2]),
        anisotropy: anisotropy_texture,
        sheen_color: sheen.color_texture,
        sheen_roughness: sheen.roughness_texture,
        ..textures
    };
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
        let at = format!("{at}.extensions.KHR_materials_specular");
        if let Some(info) = ext.specular_texture() {
            textures.specular = store.reference(source, &info, &format!("{at}.specularTexture"), warnings)?;
        }
        if let Some(info) = ext.specular_color_texture() {
            let slot = format!("{at}.specularColorTexture");
            textures.specular_color = store.reference(source, &info, &slot, warnings)?;
        }
    }
    let textured = textures.slots().iter().any(TextureRef::is_some)
        || textures.alpha_mode != ALPHA_OPAQUE
        || textures.anisotropic != 0;
    let material = Material {
        albedo: [base[0], base[1], base[2]],
        phong_exponent: phong,
        anisotropy,
        emission: [e[0] * strength, e[1] * strength, e[2] * strength],
        alpha: roughness * roughness,
        specular,
        specular_color,
        clearcoat: coat.factor,
        clearcoat_alpha: coat.roughness * coat.roughness,
        sheen_color: sheen.color,
        sheen_roughness: sheen.roughness,
        ..glass
    }
    .with_metallic(metallic, glass.transmission);
    Ok((material, textures, textured))
}

/// A material's `KHR_materials_anisotropy`: `Material::anisotropy`, anisotropyStrength s times
/// (cos θ, sin θ), θ its anisotropyRotation (zero without the extension), and its
/// anisotropyTexture (none where s is 0: the lobe is isotropic whatever the texture says).
fn read_anisotropy(
    m: &gltf::Material,
    store: &mut TextureStore,
    source: &Source,
    at: &str,
    warnings: &mut Vec<String>,
) -> Result<([f32; 2], TextureRef), SceneError> {
    let name = source.name;
    let Some(ext) = m.extension_value(ANISOTROPY) else {
        return Ok(([0.0; 2], TextureRef::NONE));
    };
    let at = format!("{at}.extensions.{ANISOTROPY}");
    if !ext.is_object() {
        return Err(SceneError::Malformed {
            path: name.into(),
            what: format!("{at}: {ext} is not an object"),
        });
    }
    let number = |key: &str| -> Result<f64, SceneError> {
        match ext.get(key) {
            None => Ok(0.0),
            Some(v) => v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| SceneError::Malformed {
                path: name.into(),
                what: format!("{at}.{key}: {v} is not a finite number"),
            }),
        }
    };
    let (strength, rotation) = (number("anisotropyStrength")?, number("anisotropyRotation")?);
    if !(0.0..=1.0).contains(&strength) {
        return Err(SceneError::Malformed {
            path: name.into(),
            what: format!("{at}.anisotropyStrength: {strength}: must lie in [0, 1]"),
        });
    }
    let factor = [(strength * rotation.cos()) as f32, (strength * rotation.sin()) as f32];
    let texture = match ext.get("anisotropyTexture") {
        Some(info) if strength > 0.0 => {
            store.json_reference(source, info, &format!("{at}.anisotropyTexture"), warnings)?
        }
        _ => TextureRef::NONE,
    };
    Ok((factor, texture))
}

/// The extension of anisotropic roughness.
pub const ANISOTROPY: &str = "KHR_materials_anisotropy";

/// The extension of the sheen layer.
pub const SHEEN: &str = "KHR_materials_sheen";

/// A material's `KHR_materials_sheen` (its numbers checked by `super::validate`).
struct Sheen {
    /// sheenColorFactor (black: no sheen).
    color: [f32; 3],
    /// sheenRoughnessFactor.
    roughness: f32,
    color_texture: TextureRef,
    roughness_texture: TextureRef,
}

/// The sheen of `m` (`shared::sheen`): its factors and the textures that multiply them (none
/// where the colour is black: the layer is off).
fn read_sheen(
    m: &gltf::Material,
    store: &mut TextureStore,
    source: &Source,
    at: &str,
    warnings: &mut Vec<String>,
) -> Result<Sheen, SceneError> {
    let mut sheen = Sheen {
        color: [0.0; 3],
        roughness: 0.0,
        color_texture: TextureRef::NONE,
        roughness_texture: TextureRef::NONE,
    };
    let Some(ext) = m.extension_value(SHEEN) else {
        return Ok(sheen);
    };
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or(0.0) as f32;
    if let Some(c) = ext.get("sheenColorFactor").and_then(serde_json::Value::as_array) {
        for (k, v) in c.iter().take(3).enumerate() {
            sheen.color[k] = number(v);
        }
    }
    sheen.roughness = ext.get("sheenRoughnessFactor").map_or(0.0, number);
    if sheen.color == [0.0; 3] {
        return Ok(sheen);
    }
    let at = format!("{at}.extensions.{SHEEN}");
    let mut slot = |key: &str, warnings: &mut Vec<String>| match ext.get(key) {
        Some(info) => store.json_reference(source, info, &format!("{at}.{key}"), warnings),
        None => Ok(TextureRef::NONE),
    };
    sheen.color_texture = slot("sheenColorTexture", warnings)?;
    sheen.roughness_texture = slot("sheenRoughnessTexture", warnings)?;
    Ok(sheen)
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
/// spec defines it: the `transmissionFactor` share of the material is a dielectric of index
/// `ior`, thin-walled without `KHR_materials_volume` (or with thicknessFactor 0), the boundary
/// of a solid with it, attenuating by Beer–Lambert with −ln(attenuationColor) /
/// attenuationDistance. (The transmissionTexture, which multiplies the factor point by point,
/// is the material textures', `shared::surface`.)
fn read_glass(m: &gltf::Material, label: &str, name: &str) -> Result<Material, SceneError> {
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
    // The interface is as rough as the material (GGX, α = roughness², set by the caller): a
    // solid's refracts, a thin wall's passes light through unbent (`shared::bsdf`).
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
    // Every material's textures entry as built (glTF's default material's first), for the
    // copies that vertex colours make.
    let mut built = vec![MaterialTextures {
        metallic: 1.0,
        roughness: 1.0,
        alpha: 1.0,
        alpha_cutoff: 0.5,
        normal_scale: 1.0,
        clearcoat_normal_scale: 1.0,
        ..Default::default()
    }];
    for m in doc.materials() {
        let (mut mat, textures, textured) = read_material(&m, &mut store, source, &mut soup.warnings)?;
        if textured {
            mat.textures = soup.material_textures.len() as u32;
            soup.material_textures.push(textures);
        }
        soup.materials.push(mat);
        built.push(textures);
    }
    let mut coloured = ColouredMaterials::new(built);
    soup.textures = store.textures;
    soup.texels = store.texels;
    // Texture coordinates are kept for every triangle where any material reads them, none
    // otherwise.
    let any_textures = soup.material_textures.len() > 1;
    let scene =
        doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| SceneError::Empty(name.into()))?;
    let placed = walk(&scene, doc.nodes().len(), name)?;
    // Every node's world matrix, for the joints of skins.
    let mut worlds = vec![None; doc.nodes().len()];
    for (node, world) in &placed {
        worlds[node.index()] = Some(*world);
    }
    for (node, world) in placed {
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
            let get = |b: gltf::Buffer| buffers.get(b.index()).map(|d| &d.0[..]);
            // A skinned mesh is placed by its joints; any other at the node's world matrix
            // times each instance's (`instancing`; a node without instances has one, the
            // identity).
            let joints = match node.skin() {
                Some(skin) => {
                    if node.extension_value(instancing::EXTENSION).is_some() {
                        return Err(SceneError::Unsupported {
                            path: name.into(),
                            what: format!(
                                "nodes[{}]: a skinned mesh with {}: smlt draws one or the other",
                                node.index(),
                                instancing::EXTENSION
                            ),
                        });
                    }
                    Some(skin::joint_matrices(&skin, &worlds, get, name)?)
                }
                None => None,
            };
            let instances = match joints {
                Some(_) => Vec::new(),
                None => instancing::transforms(&node, doc, get, name)?,
            };
            let weights = morph::weights(&node, &mesh);
            for prim in mesh.primitives() {
                let Some(local) = primitive::read(
                    get,
                    (&mesh, &prim),
                    weights,
                    placeholders,
                    (&mut soup, &mut coloured),
                    name,
                )?
                else {
                    continue;
                };
                if let Some(joints) = &joints {
                    let vertices = local.positions.len();
                    let matrices = skin::vertex_matrices(get, &prim, joints, vertices, (&local.at, name))?;
                    local.place(&Placement::per_vertex(matrices), &mut soup, any_textures, name)?;
                }
                for instance in &instances {
                    local.place(&Placement::rigid(world * *instance), &mut soup, any_textures, name)?;
                }
            }
        }
    }
    Ok(soup)
}

/// The nodes of `scene` with their world matrices, parents before children (the order in which
/// cameras and lights are numbered). glTF's node hierarchy is a set of disjoint trees: a node
/// reached twice has two parents or is its own ancestor, and is refused (a walk through a cycle
/// would never end).
fn walk<'a>(
    scene: &gltf::Scene<'a>,
    nodes: usize,
    name: &str,
) -> Result<Vec<(gltf::Node<'a>, Mat4)>, SceneError> {
    let mut reached = vec![false; nodes];
    let mut placed = Vec::new();
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
        let children: Vec<_> = node.children().map(|c| (c, world, Some(node.index()))).collect();
        stack.extend(children.into_iter().rev());
        placed.push((node, world));
    }
    Ok(placed)
}

//! Materials and their BSDFs — only what glTF scenes use: glTF's metallic-roughness BRDF
//! (`crate::metallic_roughness`; Lambertian where its dielectric layer is off), a normalised
//! Phong lobe (the paper's banner), a dielectric (glTF's transmission: glass, thin-walled or
//! solid; smooth, or rough with a GGX microfacet BSDF), and emission (area lights are emissive
//! triangles); over any of them glTF's sheen (`crate::sheen`), and over that glTF's clear coat
//! (`crate::clearcoat`).
//!
//! Surfaces are two-sided for scattering: the BSDF works on the side that `wo` lies on, and
//! `wo` and `wi` on opposite sides give 0 except through a dielectric: a smooth one's delta
//! refraction, which only [`bsdf_sample`] produces, or a rough one's transmission lobe.
//!
//! **Two normals** ([`Normals`], `crate::normals`): the lobes are evaluated and sampled in the
//! frame of the shading normal (glTF's interpolated `NORMAL`), while the geometric normal tells
//! the sides: `wo` lies on one by it, `wi` on the same side is a reflection and on the other a
//! transmission. Where the two normals disagree about a direction's side — `wo` below the
//! shading hemisphere, or `wi` reflected by the shading normal but entering the surface (or the
//! reverse) — f and the density are 0 and a sample of it fails, so a smooth surface neither
//! leaks light through itself nor lights its back from the front (pbrt-v3's choice; its cost is
//! a darker fringe where a coarse mesh's normals bend far, as in every renderer that makes it).
//! With equal normals this is exactly the one-normal BSDF. A dielectric's inside is told by the
//! geometric normal: a solid's mesh is closed with its normals outward. Emission is one-sided,
//! along the triangle's geometric normal (its winding), see [`crate::light`].
//!
//! **Normalised Phong** (Lafortune and Willems 1994), exponent n, reflectance ρ:
//! `f = ρ (n + 2)/(2π) cosⁿα`, α the angle between `wi` and the mirror direction of `wo`,
//! sampled with density `(n + 1)/(2π) cosⁿα`. For exponents up to 1e5 the lobe is a fraction
//! of a degree wide, where `1 − cos α` is of the order of f32's resolution near 1; both
//! evaluation and sampling therefore work with `δ = 1 − cos α` computed without cancellation
//! (`|r − wi|²/2` and `−expm1`), and `cosⁿα = exp(n · ln(1 − δ))` with a series for ln(1 − δ).
//!
//! **Rough dielectric** (Walter et al. 2007, "Microfacet Models for Refraction through Rough
//! Surfaces", as pbrt-v4's `DielectricBxDF`), GGX of α = roughness² (`crate::microfacet`), for
//! wo on the side of the facing normal and η = η_other / η_this:
//! - reflection: `f = D(m) G F(wo·m) / (4 |cos θ_o cos θ_i|)`, m = normalize(wo + wi);
//! - transmission: `f = D(m) G (1 − F(wo·m)) |wi·m| |wo·m| / (|cos θ_o cos θ_i| (wi·m + wo·m/η)²)`
//!   with m = normalize(η wi + wo), divided by η² for radiance (Veach's §5.2), tinted by the
//!   base colour; back-facing micro-normals give 0.
//!
//! It is sampled by a visible normal (Heitz 2018) and a choice of reflection with probability
//! [`reflection_probability`], the macro surface's Fresnel factor kept within [0.1, 0.9]: a
//! choice made before the micro-normal, so that two uniforms a bounce suffice (pbrt-v4 draws a
//! third to choose by F(wo·m)), and never 0 where either lobe can scatter.
//!
//! **A rough thin wall** (`KHR_materials_transmission` without `KHR_materials_volume`) does not
//! bend light: its transmission is its reflection lobe seen through the surface, as the
//! extension defines it — `f = D(m) G (1 − F(wo·m)) / (4 |cos θ_o cos θ_i|)` with m =
//! normalize(wo + wi'), wi' the mirror image of wi in the surface's plane, tinted, without a
//! 1/η² (the light leaves the wall as it entered) — and a transmission is sampled as a
//! reflection mirrored through the plane ([`mirrored`]).
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::clearcoat as coat;
use crate::metallic_roughness::{self as brdf, MetallicRoughness};
pub use crate::normals::Normals;
use crate::sheen;

/// A material (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Material {
    /// glTF's base colour (`baseColorFactor`): the diffuse albedo, the metal's reflectance,
    /// the Phong reflectance, a dielectric's transmission tint.
    pub albedo: [f32; 3],
    /// Phong exponent; 0: no Phong lobe (the glTF BRDF).
    pub phong_exponent: f32,
    /// Emitted radiance (glTF `emissiveFactor` × `KHR_materials_emissive_strength`).
    pub emission: [f32; 3],
    /// The share of the dielectric (`KHR_materials_transmission`'s `transmissionFactor`
    /// × (1 − metallic)); the rest is the glTF BRDF. 0: no dielectric.
    pub transmission: f32,
    /// Beer–Lambert attenuation coefficient inside a solid dielectric, per channel, in 1/m
    /// (`KHR_materials_volume`: −ln(attenuationColor) / attenuationDistance; 0: clear).
    pub attenuation: [f32; 3],
    /// The index of refraction (`KHR_materials_ior`, 1.5 by default): the dielectric's, and
    /// the glTF BRDF's dielectric layer's normal reflectance.
    pub ior: f32,
    /// 1 for a thin-walled dielectric (no `KHR_materials_volume`: light passes without
    /// bending), 0 for the boundary of a solid (the mesh encloses glass).
    pub thin_walled: u32,
    /// The GGX roughness α (glTF's roughnessFactor²) of the BRDF's specular lobe and of a
    /// solid dielectric; below [`SMOOTH_ALPHA`] they are smooth (delta lobes).
    pub alpha: f32,
    /// The metal's share of the glTF BRDF: glTF's metallicFactor m, or m / (1 − t) where the
    /// material transmits (the spec's metal keeps m of the whole).
    pub metallic: f32,
    /// `KHR_materials_specular`'s specularFactor (1 without the extension; 0: no dielectric
    /// layer, so that a non-metal is exactly Lambertian).
    pub specular: f32,
    /// `KHR_materials_specular`'s specularColorFactor.
    pub specular_color: [f32; 3],
    /// Index of the material's textures in the scene's `material_textures`
    /// (`crate::surface`); 0: none, the material is the same everywhere.
    pub textures: u32,
    /// `KHR_materials_clearcoat`'s clearcoatFactor: the coat layer's intensity over the whole
    /// material (`crate::clearcoat`); 0: no coat.
    pub clearcoat: f32,
    /// The coat's GGX roughness α (clearcoatRoughnessFactor²); below [`SMOOTH_ALPHA`] a
    /// mirror.
    pub clearcoat_alpha: f32,
    /// `KHR_materials_anisotropy`: its anisotropyStrength s times (cos θ, sin θ), θ its
    /// anisotropyRotation, the direction of the wider roughness in the tangent frame (tangent,
    /// bitangent), which `crate::surface::normals_at` turns into `Normals::anisotropy`; zero:
    /// isotropic ([`Material::alphas`]).
    pub anisotropy: [f32; 2],
    /// `KHR_materials_sheen`'s sheenColorFactor: the sheen layer's colour over the material
    /// beneath the coat (`crate::sheen`); zero: no sheen.
    pub sheen_color: [f32; 3],
    /// The sheen's roughness r (sheenRoughnessFactor; the layer's α is r², `crate::sheen::alpha`).
    pub sheen_roughness: f32,
}

/// The roughness α below which a dielectric is smooth: a GGX lobe that narrow is a mirror to
/// f32 precision.
pub const SMOOTH_ALPHA: f32 = 1e-3;

impl Material {
    /// Whether the material emits light.
    #[inline]
    pub fn is_emissive(&self) -> bool {
        self.emission[0] > 0.0 || self.emission[1] > 0.0 || self.emission[2] > 0.0
    }

    /// The material with glTF's `metallic` factor and `KHR_materials_transmission`'s
    /// `transmission` factor mixed as the spec mixes them: mix(dielectric, metal, metallic), the
    /// dielectric transmitting its transmission factor — so the glass share is
    /// t = transmission (1 − metallic), and the BRDF share 1 − t is metal by metallic / (1 − t),
    /// leaving the metal its `metallic` of the whole and the opaque dielectric
    /// (1 − metallic)(1 − transmission).
    #[inline]
    pub fn with_metallic(self, metallic: f32, transmission: f32) -> Material {
        let t = transmission * (1.0 - metallic);
        let share = if t < 1.0 { (metallic / (1.0 - t)).min(1.0) } else { 0.0 };
        Material { transmission: t, metallic: share, ..self }
    }

    /// The glTF BRDF of the material's non-transmissive share.
    #[inline]
    pub fn brdf(&self) -> MetallicRoughness {
        MetallicRoughness::new(
            Vec3::from_array(self.albedo),
            self.metallic,
            self.alphas(),
            self.ior,
            self.specular,
            Vec3::from_array(self.specular_color),
        )
    }

    /// The GGX roughnesses (αx, αy) of the BRDF's specular lobe and of a rough dielectric,
    /// along the anisotropy's direction (the local frame's x axis, `Normals::anisotropy`) and
    /// across it: `KHR_materials_anisotropy`'s mix(α, 1, s²) and α (α = roughness², s the
    /// strength); α on both where s is 0. An axis below [`SMOOTH_ALPHA`] across a rough one is
    /// kept at the limit (a lobe of zero width has no density).
    // Always on the host: the isotropic test is two compares, and out of line it was a call
    // at every BRDF evaluation.
    #[cfg_attr(not(target_arch = "spirv"), inline(always))]
    #[cfg_attr(target_arch = "spirv", inline)]
    pub fn alphas(&self) -> Vec2 {
        if self.anisotropy[0] == 0.0 && self.anisotropy[1] == 0.0 {
            return Vec2::splat(self.alpha);
        }
        let s2 = self.anisotropy[0] * self.anisotropy[0] + self.anisotropy[1] * self.anisotropy[1];
        let wide = self.alpha + (1.0 - self.alpha) * s2.min(1.0);
        let across = if wide >= SMOOTH_ALPHA { self.alpha.max(SMOOTH_ALPHA) } else { self.alpha };
        Vec2::new(wide, across)
    }

    /// Whether the material's glTF BRDF is exactly Lambertian (no metal, no dielectric layer):
    /// [`MetallicRoughness::is_lambertian`] from the factors alone, without building it.
    #[inline]
    pub fn is_lambertian(&self) -> bool {
        self.metallic == 0.0 && self.specular == 0.0
    }

    /// Whether the material has a delta lobe: a smooth dielectric, the smooth mirror of the
    /// glTF BRDF's specular lobe, or a smooth clear coat.
    #[inline]
    pub fn has_delta_lobe(&self) -> bool {
        let glass = self.transmission > 0.0 && !self.is_rough_dielectric();
        let mirror = self.transmission < 1.0 && self.phong_exponent == 0.0 && self.brdf().has_mirror();
        glass || mirror || self.has_smooth_coat()
    }

    /// Whether the material has a sheen layer (`crate::sheen`): a sheen colour not black.
    #[inline]
    pub fn has_sheen(&self) -> bool {
        self.sheen_color[0] > 0.0 || self.sheen_color[1] > 0.0 || self.sheen_color[2] > 0.0
    }

    /// The sheen colour's largest channel (the extension's `max3(sheenColor)`).
    #[inline]
    pub fn sheen_max(&self) -> f32 {
        self.sheen_color[0].max(self.sheen_color[1]).max(self.sheen_color[2])
    }

    /// Whether the material has a layer over its lobes: a clear coat or a sheen.
    #[inline]
    pub fn is_layered(&self) -> bool {
        self.clearcoat > 0.0 || self.has_sheen()
    }

    /// Whether the material has a clear coat that is a mirror (`crate::clearcoat`).
    #[inline]
    pub fn has_smooth_coat(&self) -> bool {
        self.clearcoat > 0.0 && self.clearcoat_alpha < SMOOTH_ALPHA
    }

    /// Whether the material's dielectric share is rough (a solid's or a thin wall's, of α ≥
    /// [`SMOOTH_ALPHA`]): its lobes are then not deltas.
    #[inline]
    pub fn is_rough_dielectric(&self) -> bool {
        self.transmission > 0.0 && self.alphas().max_element() >= SMOOTH_ALPHA
    }
}

/// A sampled direction with the BSDF value and the solid-angle density; `pdf == 0` means the
/// sample failed (the path ends).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction (unit).
    pub wi: Vec3,
    /// The BSDF value f(wo, wi).
    pub f: Vec3,
    /// Solid-angle density of `wi`; for a delta lobe, the probability of picking that lobe
    /// (f · |cos| / pdf is then the sample's weight, as for the others).
    pub pdf: f32,
    /// Whether `wi` comes from a delta lobe (a dielectric's mirror or refraction), which
    /// [`bsdf_eval`] and [`bsdf_pdf`] do not see.
    pub delta: bool,
}

/// What a lobe's sampler chose: nothing, a delta lobe's whole sample, or a direction whose f and
/// density are the whole material's, which [`bsdf_sample`] evaluates once for every lobe.
// One evaluation at the end, not one per lobe: the driver inlines every call, and the copies
// had made the device's compile of the shading stages 1.7× longer.
#[derive(Clone, Copy, Default)]
struct Choice {
    sample: BsdfSample,
    /// Whether `sample.wi` still needs the material's f and density.
    evaluate: bool,
}

impl Choice {
    #[inline]
    fn none() -> Self {
        Choice::default()
    }

    #[inline]
    fn delta(sample: BsdfSample) -> Self {
        Choice { sample, evaluate: false }
    }

    #[inline]
    fn direction(wi: Vec3) -> Self {
        Choice { sample: BsdfSample { wi, ..BsdfSample::default() }, evaluate: true }
    }
}

/// Two unit vectors completing `n` (unit) to an orthonormal basis (Duff et al. 2017).
// Always on the host: a call at every BSDF evaluation otherwise.
#[cfg_attr(not(target_arch = "spirv"), inline(always))]
#[cfg_attr(target_arch = "spirv", inline)]
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// A cosine-distributed direction about `n` for `u` ∈ [0,1)², density `cosθ/π`.
#[inline]
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let z = (1.0 - u.x).max(0.0).sqrt();
    let (t, b) = orthonormal_basis(n);
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * z).normalize()
}

/// ln(1 − δ) for δ ∈ [0, 1], accurate for small δ.
#[inline]
fn ln_one_minus(delta: f32) -> f32 {
    if delta < 1e-3 {
        -delta * (1.0 + delta * (0.5 + delta / 3.0))
    } else {
        (1.0 - delta).ln()
    }
}

/// 1 − e^x for x ≤ 0, accurate for small |x|.
#[inline]
fn one_minus_exp(x: f32) -> f32 {
    if x > -1e-3 {
        -x * (1.0 + x * (0.5 + x / 6.0))
    } else {
        1.0 - x.exp()
    }
}

/// cosⁿα of the Phong lobe about mirror direction `r` for direction `wi` (both unit), 0 when
/// `wi` is more than 90° from `r`.
#[inline]
pub fn phong_lobe(exponent: f32, r: Vec3, wi: Vec3) -> f32 {
    if r.dot(wi) <= 0.0 {
        return 0.0;
    }
    let delta = ((r - wi).length_squared() * 0.5).min(1.0);
    (exponent * ln_one_minus(delta)).exp()
}

/// The shading normal on the side of the surface (by the geometric normal) that `wo` is on, or
/// None where `wo` lies in the surface or below that shading hemisphere (the BSDF is 0 there).
#[inline]
fn shading_side(n: Normals, wo: Vec3) -> Option<Vec3> {
    let f = n.facing(wo);
    if f.geometric.dot(wo) > 0.0 && f.shading.dot(wo) > 0.0 {
        Some(f.shading)
    } else {
        None
    }
}

/// Whether the normals agree on the side of `w`: both put it on `wo`'s side, or both on the
/// other (always, for equal normals). Where they do not, f and the density are 0 (the module
/// doc).
#[inline]
fn sides_agree(n: Normals, wo: Vec3, w: Vec3) -> bool {
    let f = n.facing(wo);
    (f.geometric.dot(w) > 0.0) == (f.shading.dot(w) > 0.0)
}

/// The mirror direction of `wo` about `n`.
#[inline]
fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// The lobes' frame at a surface point: z the unit shading (or coat) normal, x an anisotropic
/// lobe's direction (`Normals::anisotropy`) made orthogonal to it, y = z × x; where the
/// direction is zero (an isotropic material) or lies along z, any x ([`orthonormal_basis`]).
/// Built once an evaluation, density or sample, for both its directions.
#[derive(Clone, Copy, Debug)]
pub struct LobeFrame {
    #[allow(missing_docs)] // see the struct
    pub x: Vec3,
    #[allow(missing_docs)]
    pub y: Vec3,
    #[allow(missing_docs)]
    pub z: Vec3,
}

impl LobeFrame {
    /// The frame about the unit `ns` with x along `direction` (see the struct; a unit or zero
    /// direction, so that the cut-off of its part off `ns` is absolute).
    // Always on the host: out of line it cost the path tracer 2 % of its instructions.
    #[cfg_attr(not(target_arch = "spirv"), inline(always))]
    #[cfg_attr(target_arch = "spirv", inline)]
    pub fn new(ns: Vec3, direction: Vec3) -> Self {
        if direction != Vec3::ZERO {
            let along = direction - ns * ns.dot(direction);
            let len2 = along.length_squared();
            if len2 > 1e-12 && len2.is_finite() {
                let x = along / len2.sqrt();
                return Self { x, y: ns.cross(x), z: ns };
            }
        }
        let (x, y) = orthonormal_basis(ns);
        Self { x, y, z: ns }
    }

    /// The world direction `w` in the frame.
    #[inline]
    pub fn to_local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.x), w.dot(self.y), w.dot(self.z))
    }

    /// The world direction of `v` given in the frame ([`LobeFrame::to_local`]'s inverse),
    /// normalised.
    #[inline]
    pub fn from_local(&self, v: Vec3) -> Vec3 {
        (self.x * v.x + self.y * v.y + self.z * v.z).normalize()
    }
}

/// The probability with which a rough dielectric's sample reflects, for wo at cosine `cos_o`
/// from the facing normal and relative index `eta`: the macro Fresnel factor within [0.1, 0.9].
#[inline]
pub fn reflection_probability(cos_o: f32, eta: f32) -> f32 {
    crate::float::clamp(fresnel_dielectric(cos_o, eta), 0.1, 0.9)
}

/// A micro-normal joining two directions ([`half_vector`]).
#[derive(Clone, Copy)]
struct HalfVector {
    /// The micro-normal, on wo's side.
    m: Vec3,
    /// Whether the pair is a transmission.
    transmits: bool,
    /// Whether there is one (false: a direction in the surface, or a back-facing micro-normal).
    found: bool,
}

/// The micro-normal that takes `wo` to `wi` (local, `wo.z` > 0) at a boundary of relative index
/// `eta`, on wo's side, and whether the pair is a transmission.
#[inline]
fn half_vector(wo: Vec3, wi: Vec3, eta: f32) -> HalfVector {
    let none = HalfVector { m: Vec3::Z, transmits: false, found: false };
    if wi.z == 0.0 || wo.z <= 0.0 {
        return none;
    }
    let transmits = wi.z < 0.0;
    let h = if transmits { wi * eta + wo } else { wi + wo };
    if !(h.length_squared() > 0.0) {
        return none;
    }
    let h = h.normalize();
    let m = if h.z < 0.0 { -h } else { h };
    // Back-facing micro-normals scatter nothing.
    if m.dot(wi) * wi.z < 0.0 || m.dot(wo) <= 0.0 {
        return none;
    }
    HalfVector { m, transmits, found: true }
}

/// The mirror image of the local direction `w` in the surface's plane (z = 0): a thin wall's
/// transmitted direction for a reflected one, and back.
#[inline]
pub fn mirrored(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// The rough dielectric's f(wo, wi) (local, `wo.z` > 0; the module doc's formulas), without the
/// transmission share or the tint, and whether the pair transmits; `radiance` divides a solid's
/// transmission by η²; `thin`: a thin wall, whose transmission is its reflection through the
/// plane.
// Calls on the device, not copies at every call site: the module stays ~20 % smaller.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn rough_dielectric_eval(
    alpha: Vec2,
    eta: f32,
    wo: Vec3,
    wi: Vec3,
    radiance: bool,
    thin: bool,
) -> (f32, bool) {
    let passes = thin && wi.z < 0.0;
    let wi = if passes { mirrored(wi) } else { wi };
    let h = half_vector(wo, wi, eta);
    if !h.found {
        return (0.0, false);
    }
    let m = h.m;
    let d = crate::microfacet::ggx_d(alpha, m);
    let g = crate::microfacet::smith_g(alpha, wo, wi);
    let f = fresnel_dielectric(wo.dot(m), eta);
    if !h.transmits {
        let reflected = d * g / (4.0 * wo.z * wi.z).abs();
        return if passes { (reflected * (1.0 - f), true) } else { (reflected * f, false) };
    }
    let denom = wi.dot(m) + wo.dot(m) / eta;
    let mut ft = d * g * (1.0 - f) * (wi.dot(m) * wo.dot(m)).abs() / (wo.z * wi.z * denom * denom).abs();
    if radiance {
        ft /= eta * eta;
    }
    (ft, true)
}

/// The rough dielectric's density of sampling `wi` from `wo` (local, `wo.z` > 0), without the
/// transmission share; `thin`: a thin wall's (a transmission is a mirrored reflection).
// Calls on the device, not copies at every call site: the module stays ~20 % smaller.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
fn rough_dielectric_pdf(alpha: Vec2, eta: f32, wo: Vec3, wi: Vec3, thin: bool) -> f32 {
    let passes = thin && wi.z < 0.0;
    let h = half_vector(wo, if passes { mirrored(wi) } else { wi }, eta);
    if !h.found {
        return 0.0;
    }
    let m = h.m;
    let visible = crate::microfacet::visible_normal_pdf(alpha, wo, m);
    let p_r = reflection_probability(wo.z, eta);
    if passes {
        visible / (4.0 * wo.dot(m)) * (1.0 - p_r)
    } else if h.transmits {
        let denom = wi.dot(m) + wo.dot(m) / eta;
        visible * wi.dot(m).abs() / (denom * denom) * (1.0 - p_r)
    } else {
        visible / (4.0 * wo.dot(m)) * p_r
    }
}

/// f(wo, wi) at a surface with normals `n` (all unit; `wo` and `wi` point away); `radiance` is
/// the transport mode (see [`dielectric_sample`]; a rough dielectric's transmission and the
/// clear coat's weight depend on it): the material's lobes under its sheen (`crate::sheen`)
/// under its clear coat (`crate::clearcoat`).
// Calls on the device, not copies at every call site: the module stays ~20 % smaller.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn bsdf_eval(m: &Material, n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> Vec3 {
    if m.is_layered() {
        return layered_eval(m, n, wo, wi, radiance);
    }
    base_eval(m, n, wo, wi, radiance)
}

/// [`bsdf_eval`] of a material with layers over its lobes' f (`base`): the sheen's
/// `c f_sheen + s base`, then the coat's `(1 − w) · that + w f_coat`.
// Out of line and cold: materials without layers pay a compare and a call site for them (2–4 %
// of `pt`'s and naive's time, `results/cpu-path/clearcoat/`).
#[cold]
#[inline(never)]
fn layered_eval(m: &Material, n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> Vec3 {
    let base = base_eval(m, n, wo, wi, radiance);
    let f = n.facing(wo);
    let mut under = base;
    if m.has_sheen() {
        under = sheen_eval(m, n, wo, wi, base);
    }
    if !(m.clearcoat > 0.0) {
        return under;
    }
    let w = coat::layer_weight(m.clearcoat, coat::viewer_cosine(f.coat, wo, wi, radiance));
    under * (1.0 - w) + Vec3::splat(w * coat_eval(m, f, wo, wi, radiance))
}

/// The sheen layer over the lobes' f `base` ([`crate::sheen`]): `c f_sheen + s base`, the
/// layer in the shading normal's frame (where the callers' cosine is taken), on `wo`'s side.
#[inline]
fn sheen_eval(m: &Material, n: Normals, wo: Vec3, wi: Vec3, base: Vec3) -> Vec3 {
    let Some(ns) = shading_side(n, wo) else {
        return Vec3::ZERO;
    };
    let (cos_o, cos_i) = (ns.dot(wo), ns.dot(wi));
    let s = sheen::albedo_scaling(m.sheen_max(), m.sheen_roughness, cos_o, cos_i);
    let mut f = base * s;
    if cos_i > 0.0 && sides_agree(n, wo, wi) {
        let frame = LobeFrame::new(ns, Vec3::ZERO);
        let layer = sheen::eval(sheen::alpha(m.sheen_roughness), frame.to_local(wo), frame.to_local(wi));
        f += Vec3::from_array(m.sheen_color) * layer;
    }
    f
}

/// The coat's layer `f_coat(wo, wi)` in its own frame (`f` the normals facing `wo`), as the
/// callers' shading cosine takes it ([`coat::frame_correction`]); 0 unless both directions lie
/// above the coat by its normal and the geometric one (the shading normal, which the base's
/// normal texture bent, does not limit the coat).
#[inline]
fn coat_eval(m: &Material, f: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> f32 {
    let nc = f.coat;
    if !(above_coat(f, wo) && above_coat(f, wi)) {
        return 0.0;
    }
    let frame = LobeFrame::new(nc, Vec3::ZERO);
    let layer = coat::eval(m.clearcoat_alpha, frame.to_local(wo), frame.to_local(wi));
    if !(layer > 0.0) {
        return 0.0;
    }
    layer * coat::frame_correction(nc, f.shading, if radiance { wi } else { wo })
}

/// Whether `w` lies above the coat: by its normal and the geometric one (`f` facing `wo`).
#[inline]
fn above_coat(f: Normals, w: Vec3) -> bool {
    f.coat.dot(w) > 0.0 && f.geometric.dot(w) > 0.0
}

/// f(wo, wi) of the material's lobes without its layers ([`bsdf_eval`]).
// Calls on the device, not copies at every call site: the module stays ~20 % smaller; on the
// host the unlayered path of `bsdf_eval`, whole.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline(always))]
fn base_eval(m: &Material, n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> Vec3 {
    base_lobes::<true, false>(m, n, wo, wi, radiance).0
}

/// The density of sampling `wi` from the material's lobes without its layers ([`bsdf_pdf`]).
// As `base_eval`.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline(always))]
fn base_pdf(m: &Material, n: Normals, wo: Vec3, wi: Vec3) -> f32 {
    base_lobes::<false, true>(m, n, wo, wi, true).1
}

/// Both of [`base_eval`] and [`base_pdf`] at once ([`bsdf_eval_pdf`]).
// As `base_eval`: one more function on the device, for the path tracer's two calls.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline(always))]
fn base_eval_pdf(m: &Material, n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> (Vec3, f32) {
    base_lobes::<true, true>(m, n, wo, wi, radiance)
}

/// f(wo, wi) of the material's lobes without its layers where `F`, and the density of
/// sampling `wi` from them where `PDF` (zero otherwise): one pass over the normals' sides, the
/// lobe's frame and the local directions for both. The parts not asked for are not compiled:
/// a constant generic's branch is decided as the function is instantiated, on the device too.
#[inline(always)]
fn base_lobes<const F: bool, const PDF: bool>(
    m: &Material,
    n: Normals,
    wo: Vec3,
    wi: Vec3,
    radiance: bool,
) -> (Vec3, f32) {
    let none = (Vec3::ZERO, 0.0);
    let Some(ns) = shading_side(n, wo) else {
        return none;
    };
    if !sides_agree(n, wo, wi) {
        return none;
    }
    let t = m.transmission;
    if m.is_rough_dielectric() {
        let eta = relative_ior(m, n.geometric, wo);
        let frame = LobeFrame::new(ns, n.anisotropy);
        let (wo_l, wi_l) = (frame.to_local(wo), frame.to_local(wi));
        let thin = m.thin_walled != 0;
        let (f_brdf, pdf_brdf) = brdf_lobes::<F, PDF>(m, n, ns, wo, wi);
        let f = if F {
            let (f, transmits) = rough_dielectric_eval(m.alphas(), eta, wo_l, wi_l, radiance, thin);
            let tint = if transmits { Vec3::from_array(m.albedo) } else { Vec3::ONE };
            tint * (t * f) + f_brdf * (1.0 - t)
        } else {
            Vec3::ZERO
        };
        let pdf = if PDF {
            t * rough_dielectric_pdf(m.alphas(), eta, wo_l, wi_l, thin) + (1.0 - t) * pdf_brdf
        } else {
            0.0
        };
        return (f, pdf);
    }
    if t > 0.0 {
        let (f_brdf, pdf_brdf) = brdf_lobes::<F, PDF>(m, n, ns, wo, wi);
        (f_brdf * (1.0 - t), (1.0 - t) * pdf_brdf)
    } else if m.phong_exponent > 0.0 {
        if ns.dot(wi) <= 0.0 {
            return none;
        }
        let e = m.phong_exponent;
        let lobe = phong_lobe(e, reflect(wo, ns), wi);
        (Vec3::from_array(m.albedo) * ((e + 2.0) / (2.0 * PI) * lobe), (e + 1.0) / (2.0 * PI) * lobe)
    } else {
        brdf_lobes::<F, PDF>(m, n, ns, wo, wi)
    }
}

/// The glTF BRDF's f(wo, wi) where `F` and its sampling's density of wi where `PDF`, for wo on
/// the side of the unit normal `ns` (`n` for the lobe's anisotropy).
// Always: the Lambert test is a few compares, and a call here cost the path tracer 3 %.
#[inline(always)]
fn brdf_lobes<const F: bool, const PDF: bool>(
    m: &Material,
    n: Normals,
    ns: Vec3,
    wo: Vec3,
    wi: Vec3,
) -> (Vec3, f32) {
    if m.is_lambertian() {
        let cos_i = ns.dot(wi);
        if !(cos_i > 0.0) {
            return (Vec3::ZERO, 0.0);
        }
        return (Vec3::from_array(m.albedo) / PI, cos_i / PI);
    }
    let frame = LobeFrame::new(ns, n.anisotropy);
    let (wo_l, wi_l) = (frame.to_local(wo), frame.to_local(wi));
    let b = m.brdf();
    let f = if F { brdf::eval(&b, wo_l, wi_l) } else { Vec3::ZERO };
    let pdf = if PDF { brdf::pdf(&b, wo_l, wi_l) } else { 0.0 };
    (f, pdf)
}

/// Solid-angle density with which [`bsdf_sample`] picks `wi` given `wo`, without the delta
/// lobes' discrete probabilities.
// Calls on the device, not copies at every call site: the module stays ~20 % smaller.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn bsdf_pdf(m: &Material, n: Normals, wo: Vec3, wi: Vec3) -> f32 {
    if m.is_layered() {
        return layered_pdf(m, n, wo, wi);
    }
    base_pdf(m, n, wo, wi)
}

/// [`bsdf_eval`] and [`bsdf_pdf`] of the same directions at once, sharing their work: a light
/// sample's value and its weight against the BSDF's sampling; the value of a direction the BSDF
/// sampled and its density.
#[inline]
pub fn bsdf_eval_pdf(m: &Material, n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> (Vec3, f32) {
    if m.is_layered() {
        return (layered_eval(m, n, wo, wi, radiance), layered_pdf(m, n, wo, wi));
    }
    base_eval_pdf(m, n, wo, wi, radiance)
}

/// [`bsdf_pdf`] of a material with layers: the density of its lobes beneath them, the sheen's
/// share and then the coat's.
// Out of line and cold: materials without layers pay a compare and a call site for them (2–4 %
// of `pt`'s and naive's time, `results/cpu-path/clearcoat/`).
#[cold]
#[inline(never)]
fn layered_pdf(m: &Material, n: Normals, wo: Vec3, wi: Vec3) -> f32 {
    let base = base_pdf(m, n, wo, wi);
    let f = n.facing(wo);
    let mut under = base;
    if m.has_sheen() {
        under = match shading_side(n, wo) {
            Some(ns) => {
                let p = sheen::probability(m.sheen_max(), m.sheen_roughness, ns.dot(wo));
                let layer = if ns.dot(wi) > 0.0 && sides_agree(n, wo, wi) { sheen::PDF } else { 0.0 };
                (1.0 - p) * base + p * layer
            }
            None => 0.0,
        };
    }
    if !(m.clearcoat > 0.0) {
        return under;
    }
    let nc = f.coat;
    let p = coat::probability(m.clearcoat, nc.dot(wo));
    let layer = if above_coat(f, wo) && above_coat(f, wi) {
        let frame = LobeFrame::new(nc, Vec3::ZERO);
        coat::pdf(m.clearcoat_alpha, frame.to_local(wo), frame.to_local(wi))
    } else {
        0.0
    };
    (1.0 - p) * under + p * layer
}

/// Unpolarised Fresnel reflectance of a smooth dielectric boundary for light at cosine
/// `cos_i` > 0 from the normal, on the side from which the other side's relative index of
/// refraction is `eta` (η_other / η_this); 1 beyond the critical angle (total internal
/// reflection).
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// The direction refracted from `wo` (unit, on the side of the unit normal `ns`) into the other
/// side, of relative index `eta` (Snell's law); None beyond the critical angle.
#[inline]
pub fn refract(wo: Vec3, ns: Vec3, eta: f32) -> Option<Vec3> {
    let cos_o = ns.dot(wo);
    let sin2_t = (1.0 - cos_o * cos_o).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wo / eta + ns * (cos_o / eta - cos_t)).normalize())
}

/// The relative index of refraction of the side `wo` is not on, seen from `wo`'s side, of a
/// dielectric with geometric (outward) normal `n`: ior entering, 1/ior leaving; a thin wall
/// has glass on neither side but reflects as an ior boundary.
#[inline]
pub fn relative_ior(m: &Material, n: Vec3, wo: Vec3) -> f32 {
    if m.thin_walled != 0 || n.dot(wo) >= 0.0 {
        m.ior
    } else {
        1.0 / m.ior
    }
}

/// The Beer–Lambert attenuation coefficient along a ray leaving a surface of material `m`
/// (geometric normal `n`) in direction `d`: the glass's inside a solid dielectric, 0 elsewhere.
#[inline]
pub fn medium_coefficient(m: &Material, n: Vec3, d: Vec3) -> Vec3 {
    if m.transmission > 0.0 && m.thin_walled == 0 && n.dot(d) < 0.0 {
        Vec3::from_array(m.attenuation)
    } else {
        Vec3::ZERO
    }
}

/// Beer–Lambert transmittance exp(−σ d) over `distance` through a medium of coefficient
/// `sigma` (per channel).
#[inline]
pub fn transmittance(sigma: Vec3, distance: f32) -> Vec3 {
    Vec3::new((-sigma.x * distance).exp(), (-sigma.y * distance).exp(), (-sigma.z * distance).exp())
}

/// Samples the dielectric lobes of a transmissive material — smooth: mirror with probability
/// t·F, refraction, or a thin wall's straight passage, with t·(1 − F); rough: the module doc's
/// sampling, with t — or its Lambertian rest (1 − t). `radiance`: the sample is for radiance transport (a camera subpath, the path
/// tracer), where refraction scales radiance by 1/η² (Veach's thesis §5.2); importance
/// transport (a light subpath) takes the adjoint, which does not.
#[inline]
fn dielectric_sample(m: &Material, n: Normals, ns: Vec3, wo: Vec3, u: Vec2, radiance: bool) -> Choice {
    let t = m.transmission;
    if u.x >= t {
        let v = Vec2::new(((u.x - t) / (1.0 - t)).min(1.0 - f32::EPSILON), u.y);
        return brdf_sample(m, n, ns, wo, v, 1.0 - t);
    }
    let v = u.x / t;
    let eta = relative_ior(m, n.geometric, wo);
    if m.is_rough_dielectric() {
        // Reflect or transmit first (by the macro Fresnel factor), then a visible normal.
        let p_r = reflection_probability(ns.dot(wo), eta);
        let reflects = v < p_r;
        let w = if reflects { v / p_r } else { (v - p_r) / (1.0 - p_r) };
        let frame = LobeFrame::new(ns, n.anisotropy);
        let ml = crate::microfacet::sample_visible_normal(
            m.alphas(),
            frame.to_local(wo),
            Vec2::new(w.min(1.0 - f32::EPSILON), u.y),
        );
        let micro = frame.from_local(ml);
        let wi = if reflects {
            reflect(wo, micro)
        } else if m.thin_walled != 0 {
            // Through a thin wall: the reflection, mirrored through the plane.
            let r = reflect(wo, micro);
            r - ns * (2.0 * ns.dot(r))
        } else {
            match refract(wo, micro, eta) {
                Some(wi) => wi,
                None => return Choice::none(),
            }
        };
        // A reflection must stay on wo's side and a refraction leave it.
        if (ns.dot(wi) > 0.0) != reflects {
            return Choice::none();
        }
        return Choice::direction(wi);
    }
    let f_r = fresnel_dielectric(ns.dot(wo), eta);
    let refracted = if m.thin_walled != 0 { Some(-wo) } else { refract(wo, ns, eta) };
    match refracted {
        Some(wi) if v >= f_r => {
            let cos_i = ns.dot(wi).abs();
            let pdf = t * (1.0 - f_r);
            let scale = if radiance && m.thin_walled == 0 { 1.0 / (eta * eta) } else { 1.0 };
            if !(cos_i > 0.0) {
                return Choice::none();
            }
            Choice::delta(BsdfSample {
                wi,
                f: Vec3::from_array(m.albedo) * (pdf * scale / cos_i),
                pdf,
                delta: true,
            })
        }
        _ => {
            let wi = reflect(wo, ns);
            let cos_i = ns.dot(wi);
            let pdf = t * f_r;
            if !(cos_i > 0.0 && pdf > 0.0) {
                return Choice::none();
            }
            Choice::delta(BsdfSample { wi, f: Vec3::splat(pdf / cos_i), pdf, delta: true })
        }
    }
}

/// Samples `wi` for `wo` with `u` ∈ [0,1)²; `radiance` is the transport mode (see
/// [`dielectric_sample`] and `crate::clearcoat`; the other lobes are reciprocal).
#[inline]
pub fn bsdf_sample(m: &Material, n: Normals, wo: Vec3, u: Vec2, radiance: bool) -> BsdfSample {
    let choice = if m.is_layered() {
        layered_sample(m, n, wo, u, radiance)
    } else {
        match shading_side(n, wo) {
            Some(ns) => base_sample(m, n, ns, wo, u, radiance),
            None => Choice::none(),
        }
    };
    if !choice.evaluate {
        return choice.sample;
    }
    let wi = choice.sample.wi;
    let (f, pdf) = bsdf_eval_pdf(m, n, wo, wi, radiance);
    if !(pdf > 0.0) {
        return BsdfSample::default();
    }
    BsdfSample { wi, f, pdf, delta: false }
}

/// The lobes beneath the layers' sample, `ns` the shading normal on `wo`'s side.
#[inline]
fn base_sample(m: &Material, n: Normals, ns: Vec3, wo: Vec3, u: Vec2, radiance: bool) -> Choice {
    let choice = lobe_sample(m, n, ns, wo, u, radiance);
    // A delta lobe's direction where the normals disagree on its side fails (the others'
    // densities are 0 there already).
    if choice.sample.delta && !sides_agree(n, wo, choice.sample.wi) {
        return Choice::none();
    }
    choice
}

/// [`bsdf_sample`] of a material with layers: the coat with [`coat::probability`]
/// ([`coat_sample`]), else the sheen with [`sheen::probability`] (a direction uniform over the
/// shading hemisphere), else the lobes beneath (none where `wo` lies below the shading normal's
/// hemisphere), whose delta samples the layers' weights and probabilities scale (their other
/// samples' f and density are the whole material's already).
// Out of line and cold: materials without layers pay a compare and a call site for them, and
// the device module keeps one copy.
#[cold]
#[inline(never)]
fn layered_sample(m: &Material, n: Normals, wo: Vec3, u: Vec2, radiance: bool) -> Choice {
    let nc = n.facing(wo).coat;
    let p_coat = if m.clearcoat > 0.0 { coat::probability(m.clearcoat, nc.dot(wo)) } else { 0.0 };
    if u.x < p_coat {
        let v = Vec2::new((u.x / p_coat).min(1.0 - f32::EPSILON), u.y);
        return coat_sample(m, n, wo, v, radiance, p_coat);
    }
    let Some(ns) = shading_side(n, wo) else {
        return Choice::none();
    };
    let mut v = Vec2::new(((u.x - p_coat) / (1.0 - p_coat)).min(1.0 - f32::EPSILON), u.y);
    let p_sheen =
        if m.has_sheen() { sheen::probability(m.sheen_max(), m.sheen_roughness, ns.dot(wo)) } else { 0.0 };
    if v.x < p_sheen {
        let w = Vec2::new((v.x / p_sheen).min(1.0 - f32::EPSILON), v.y);
        return Choice::direction(LobeFrame::new(ns, Vec3::ZERO).from_local(sheen::sample(w)));
    }
    v.x = ((v.x - p_sheen) / (1.0 - p_sheen)).min(1.0 - f32::EPSILON);
    let mut choice = base_sample(m, n, ns, wo, v, radiance);
    if choice.sample.delta {
        let wi = choice.sample.wi;
        let s = if m.has_sheen() {
            sheen::albedo_scaling(m.sheen_max(), m.sheen_roughness, ns.dot(wo), ns.dot(wi))
        } else {
            1.0
        };
        let w = if m.clearcoat > 0.0 {
            coat::layer_weight(m.clearcoat, coat::viewer_cosine(nc, wo, wi, radiance))
        } else {
            0.0
        };
        choice.sample.f *= s * (1.0 - w);
        choice.sample.pdf *= (1.0 - p_sheen) * (1.0 - p_coat);
    }
    choice
}

/// The coat's sample for `wo` with `u` ∈ [0,1)², chosen with probability `p`: in its own frame
/// (`crate::clearcoat`), its mirror a delta of weight w over `p`.
#[inline]
fn coat_sample(m: &Material, n: Normals, wo: Vec3, u: Vec2, radiance: bool, p: f32) -> Choice {
    let f = n.facing(wo);
    let nc = f.coat;
    let frame = LobeFrame::new(nc, Vec3::ZERO);
    let sampled =
        if above_coat(f, wo) { coat::sample(m.clearcoat_alpha, frame.to_local(wo), u) } else { None };
    let Some(local) = sampled else {
        return Choice::none();
    };
    let wi = frame.from_local(local);
    if !above_coat(f, wi) {
        return Choice::none();
    }
    if m.has_smooth_coat() {
        // The mirror: its weight w over its probability (the viewer's cosine is wo's and wi's
        // alike), as the callers' shading cosine takes it.
        let w = coat::layer_weight(m.clearcoat, nc.dot(wo));
        let correction = coat::frame_correction(nc, f.shading, if radiance { wi } else { wo });
        let cos_c = nc.dot(wi);
        if !(correction > 0.0 && cos_c > 0.0) {
            return Choice::none();
        }
        return Choice::delta(BsdfSample { wi, f: Vec3::splat(w * correction / cos_c), pdf: p, delta: true });
    }
    Choice::direction(wi)
}

/// [`bsdf_sample`]'s lobes beneath the coat, `ns` the shading normal on `wo`'s side.
#[inline]
fn lobe_sample(m: &Material, n: Normals, ns: Vec3, wo: Vec3, u: Vec2, radiance: bool) -> Choice {
    if m.transmission > 0.0 {
        return dielectric_sample(m, n, ns, wo, u, radiance);
    }
    if m.phong_exponent <= 0.0 {
        return brdf_sample(m, n, ns, wo, u, 1.0);
    }
    // cos α = (1 − u)^(1/(n+1)), computed as exp(x) with 1 − cos α = −expm1(x).
    let x = (1.0 - u.x).ln() / (m.phong_exponent + 1.0);
    let cos_a = x.exp();
    let sin_a = (one_minus_exp(x) * (1.0 + cos_a)).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let r = reflect(wo, ns);
    let (t, b) = orthonormal_basis(r);
    Choice::direction((t * (sin_a * phi.cos()) + b * (sin_a * phi.sin()) + r * cos_a).normalize())
}

/// Samples the glTF BRDF of `m` (`ns` the shading normal on wo's side), which is the `share`
/// of the material: its mirror as a delta of that share's probability, any other direction
/// to be evaluated as the whole material.
// Always: the Lambert test is a few compares, and a call here cost the path tracer 3 %.
#[inline(always)]
fn brdf_sample(m: &Material, n: Normals, ns: Vec3, wo: Vec3, u: Vec2, share: f32) -> Choice {
    if m.is_lambertian() {
        return Choice::direction(cosine_hemisphere(ns, u));
    }
    let frame = LobeFrame::new(ns, n.anisotropy);
    let s = brdf::sample(&m.brdf(), frame.to_local(wo), u);
    if !s.found {
        return Choice::none();
    }
    let wi = frame.from_local(s.wi);
    if !s.delta {
        return Choice::direction(wi);
    }
    // As the glass's mirror: f · cos θ_i / pdf is the reflected share over its probability.
    let (pdf, cos_i) = (s.pdf * share, ns.dot(wi));
    if !(pdf > 0.0 && cos_i > 0.0) {
        return Choice::none();
    }
    Choice::delta(BsdfSample { wi, f: s.f * (share / cos_i), pdf, delta: true })
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;

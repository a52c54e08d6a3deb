//! The environment light: radiance arriving from infinitely far away in every direction, given
//! as a latitude-longitude image (a sky), or a constant colour (a 1 × 1 image). It is
//! importance-sampled by a piecewise-constant 2D distribution over its texels, each weighted
//! by its luminance times sin θ (pbrt-v3's `InfiniteAreaLight`, pbrt-v4's
//! `ImageInfiniteLight`), and looked up at the nearest texel, so that the density is exactly
//! proportional to the radiance it samples within each row.
//!
//! **Directions.** +Y is up (glTF's). A direction `d` in the map's frame has the image
//! coordinates of Mitsuba 3's `envmap`: `u = atan2(d.x, −d.z) / 2π` (wrapped into [0, 1)),
//! `v = acos(d.y) / π`: the image's top row is the zenith, its left edge −Z, its centre column
//! +Z and its first quarter +X.
//! The map is turned about +Y by [`Environment::rotation`] (world = R_y · map, the rotation
//! Mitsuba's `to_world` would give).
//!
//! **Densities.** A texel of the w × h image covers (2π/w)(π/h) in (φ, θ), so the solid-angle
//! density of direction d is `p_uv(u, v) / (2π² sin θ)` ([`Environment::pdf`]).
//!
//! **Light subpaths** leave it as they leave a directional light (`crate::distant`): a
//! direction from the distribution, then a uniform point on the disk of the scene's bounding
//! sphere perpendicular to it ([`Environment::sample_origin`]); its first vertex's density is
//! the disk's, projected.
//!
//! **The buffer** (`environment_map`): per texel, row after row from the top, its rgb radiance
//! (the strength applied) and its row's running CDF (4 floats); then the marginal CDF over the
//! rows (h floats). Each CDF ends at exactly 1.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::color::luminance;
use crate::distant;

/// The environment light's description (uploaded to the device as it is; its texels and CDFs
/// are in the `environment_map` buffer, see the module doc).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Environment {
    /// Image width in texels (0: the scene has no environment light).
    pub width: u32,
    /// Image height in texels.
    pub height: u32,
    /// Offset of the marginal CDF in the buffer (4 · width · height).
    pub marginal: u32,
    /// Padding.
    pub _pad: u32,
    /// (cos ρ, sin ρ) of the rotation ρ about +Y from the map's frame to the world.
    pub rotation: [f32; 2],
    /// The mean over the texels of [`texel_weight`]: the normaliser of the density.
    pub mean_weight: f32,
    /// The probability with which the light CDF picks the environment.
    pub pick: f32,
    /// Centre of the scene's bounding sphere (of the disk light subpaths start on).
    pub centre: [f32; 3],
    /// Radius of the scene's bounding sphere.
    pub radius: f32,
}

/// The environment of a scene without one.
pub const NONE: Environment = Environment {
    width: 0,
    height: 0,
    marginal: 0,
    _pad: 0,
    rotation: [1.0, 0.0],
    mean_weight: 0.0,
    pick: 0.0,
    centre: [0.0; 3],
    radius: 0.0,
};

/// A direction sampled on the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentSample {
    /// Unit direction towards the environment (from the scene).
    pub wi: Vec3,
    /// Radiance arriving from `wi`.
    pub radiance: Vec3,
    /// Solid-angle density of `wi` (not including the light pick).
    pub pdf: f32,
}

/// The sampling weight of a texel of radiance `rgb` in row `row` of `height`: its luminance
/// times the sine of its row centre's polar angle (the solid angle it covers).
#[inline]
pub fn texel_weight(rgb: Vec3, row: u32, height: u32) -> f32 {
    let theta = PI * (row as f32 + 0.5) / height as f32;
    luminance(rgb).max(0.0) * theta.sin()
}

/// Image coordinates (u, v) ∈ [0, 1]² of a unit direction in the map's frame.
#[inline]
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let mut u = d.x.atan2(-d.z) * (0.5 / PI);
    if u < 0.0 {
        u += 1.0;
    }
    Vec2::new(u, crate::float::clamp(d.y, -1.0, 1.0).acos() / PI)
}

/// The unit direction in the map's frame of image coordinates (u, v).
#[inline]
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let phi = 2.0 * PI * uv.x;
    let theta = PI * uv.y;
    let s = theta.sin();
    Vec3::new(s * phi.sin(), theta.cos(), -s * phi.cos())
}

/// The index of the first of `cdf[offset .. offset + n]` that exceeds `u` (the last when none
/// does), and where `u` falls within that entry's step, in [0, 1).
#[inline]
fn invert_cdf(buffer: &[f32], offset: u32, stride: u32, n: u32, u: f32) -> (u32, f32) {
    let mut lo = 0u32;
    let mut hi = n - 1;
    while lo < hi {
        let mid = (lo + hi) / 2;
        if buffer[(offset + mid * stride) as usize] > u {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    let below = if lo > 0 { buffer[(offset + (lo - 1) * stride) as usize] } else { 0.0 };
    let above = buffer[(offset + lo * stride) as usize];
    let within =
        if above > below { crate::float::clamp((u - below) / (above - below), 0.0, 0.99999994) } else { 0.5 };
    (lo, within)
}

impl Environment {
    /// Whether the scene has an environment light.
    #[inline]
    pub fn is_present(&self) -> bool {
        self.width > 0
    }

    #[inline]
    /// A direction in the map's frame, in the world's.
    fn map_to_world(&self, d: Vec3) -> Vec3 {
        let (c, s) = (self.rotation[0], self.rotation[1]);
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    #[inline]
    /// A direction in the world's frame, in the map's.
    fn world_to_map(&self, d: Vec3) -> Vec3 {
        let (c, s) = (self.rotation[0], self.rotation[1]);
        Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
    }

    /// The texel (column, row) at image coordinates `uv`.
    #[inline]
    fn texel_at(&self, uv: Vec2) -> (u32, u32) {
        let i = ((uv.x * self.width as f32) as u32).min(self.width - 1);
        let j = ((uv.y * self.height as f32) as u32).min(self.height - 1);
        (i, j)
    }

    #[inline]
    fn texel(&self, map: &[f32], i: u32, j: u32) -> Vec3 {
        let k = (4 * (j * self.width + i)) as usize;
        Vec3::new(map[k], map[k + 1], map[k + 2])
    }

    /// Radiance arriving from the unit world direction `wi` (0 without an environment).
    #[inline]
    pub fn radiance(&self, map: &[f32], wi: Vec3) -> Vec3 {
        if !self.is_present() {
            return Vec3::ZERO;
        }
        let (i, j) = self.texel_at(direction_to_uv(self.world_to_map(wi)));
        self.texel(map, i, j)
    }

    /// The solid-angle density with which [`Self::sample`] picks the unit world direction `wi`
    /// (not including the light pick).
    #[inline]
    pub fn pdf(&self, map: &[f32], wi: Vec3) -> f32 {
        if !self.is_present() || !(self.mean_weight > 0.0) {
            return 0.0;
        }
        let d = self.world_to_map(wi);
        let sin_theta = (1.0 - d.y * d.y).max(0.0).sqrt();
        if !(sin_theta > 0.0) {
            return 0.0;
        }
        let (i, j) = self.texel_at(direction_to_uv(d));
        let pdf_uv = texel_weight(self.texel(map, i, j), j, self.height) / self.mean_weight;
        pdf_uv / (2.0 * PI * PI * sin_theta)
    }

    /// A direction towards the environment for `u` ∈ [0,1)²: a row by the marginal CDF, a
    /// texel in it by the row's CDF, a uniform point in the texel.
    #[inline]
    pub fn sample(&self, map: &[f32], u: Vec2) -> EnvironmentSample {
        let none = EnvironmentSample { wi: Vec3::Y, radiance: Vec3::ZERO, pdf: 0.0 };
        if !self.is_present() || !(self.mean_weight > 0.0) {
            return none;
        }
        let (j, dv) = invert_cdf(map, self.marginal, 1, self.height, u.y);
        let (i, du) = invert_cdf(map, 4 * j * self.width + 3, 4, self.width, u.x);
        // Off the poles, where f32 rounding of the last row could land (sin θ = 0 there).
        let v = ((j as f32 + dv) / self.height as f32).clamp(1e-7, 0.99999994);
        let uv = Vec2::new((i as f32 + du) / self.width as f32, v);
        let d = uv_to_direction(uv);
        let sin_theta = (PI * v).sin();
        let rgb = self.texel(map, i, j);
        if !(sin_theta > 0.0) {
            return none;
        }
        let pdf_uv = texel_weight(rgb, j, self.height) / self.mean_weight;
        EnvironmentSample {
            wi: self.map_to_world(d),
            radiance: rgb,
            pdf: pdf_uv / (2.0 * PI * PI * sin_theta),
        }
    }

    /// The origin of a light subpath arriving along the unit direction `travel` (−wi) for `u`
    /// ∈ [0,1)²: a point on the bounding sphere's disk (`crate::distant`), area density
    /// [`Self::pdf_origin`].
    #[inline]
    pub fn sample_origin(&self, travel: Vec3, u: Vec2) -> Vec3 {
        distant::disk_origin(Vec3::from_array(self.centre), self.radius, travel, u)
    }

    /// The area density of [`Self::sample_origin`] on its disk, 1 / (π r²).
    #[inline]
    pub fn pdf_origin(&self) -> f32 {
        distant::disk_pdf(self.radius)
    }

    /// Where a shadow ray from `p` towards the environment along `wi` ends: a point outside
    /// the bounding sphere.
    #[inline]
    pub fn beyond(&self, p: Vec3, wi: Vec3) -> Vec3 {
        distant::beyond(Vec3::from_array(self.centre), self.radius, p, wi)
    }
}

/// An environment light built on the host: its description and its buffer.
#[cfg(not(target_arch = "spirv"))]
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// The description ([`Environment::pick`], `centre` and `radius` are the scene's to set).
    pub environment: Environment,
    /// The buffer (the module doc's layout).
    pub map: std::vec::Vec<f32>,
}

#[cfg(not(target_arch = "spirv"))]
impl EnvironmentMap {
    /// The environment of a `width` × `height` image of linear rgb radiance `texels` (row
    /// after row from the top), rotated by `rotation` radians about +Y. Texels must be finite
    /// and non-negative.
    pub fn new(width: u32, height: u32, texels: &[[f32; 3]], rotation: f32) -> Self {
        assert!(width > 0 && height > 0 && texels.len() == (width * height) as usize);
        let (w, h) = (width as usize, height as usize);
        let mut map = vec![0.0f32; 4 * w * h + h];
        let mut row_sums = vec![0.0f64; h];
        for j in 0..h {
            let weights: std::vec::Vec<f64> = (0..w)
                .map(|i| texel_weight(Vec3::from_array(texels[j * w + i]), j as u32, height) as f64)
                .collect();
            let sum: f64 = weights.iter().sum();
            row_sums[j] = sum;
            let mut running = 0.0f64;
            for i in 0..w {
                running += weights[i];
                let k = 4 * (j * w + i);
                map[k..k + 3].copy_from_slice(&texels[j * w + i]);
                // A black row is never picked; its CDF is uniform.
                map[k + 3] = if sum > 0.0 { (running / sum) as f32 } else { (i + 1) as f32 / w as f32 };
            }
            map[4 * (j * w + w - 1) + 3] = 1.0;
        }
        let total: f64 = row_sums.iter().sum();
        let mut running = 0.0f64;
        for j in 0..h {
            running += row_sums[j];
            map[4 * w * h + j] =
                if total > 0.0 { (running / total) as f32 } else { (j + 1) as f32 / h as f32 };
        }
        map[4 * w * h + h - 1] = 1.0;
        let environment = Environment {
            width,
            height,
            marginal: (4 * w * h) as u32,
            rotation: [rotation.cos(), rotation.sin()],
            mean_weight: (total / (w * h) as f64) as f32,
            ..NONE
        };
        Self { environment, map }
    }

    /// ∫ luminance(L(ω)) dω over the sphere: with the bounding sphere's r², what the light CDF
    /// picks the environment by (the flux through its disk over π, the scale of
    /// `crate::light`).
    pub fn luminance_integral(&self) -> f64 {
        // Σ weight · (2π/w)(π/h) over the texels, the weights' mean times 2π².
        let pi = std::f64::consts::PI;
        self.environment.mean_weight as f64 * 2.0 * pi * pi
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;

//! The pinhole perspective camera, with the importance function and directional density of
//! pbrt-v3's `PerspectiveCamera` (the lens area is 1 and the film plane lies at distance 1):
//! with A the area of the film's image on the plane at distance 1 and θ the angle between a
//! ray and the view direction, `We = 1 / (A cos⁴θ)` and `p_dir = 1 / (A cos³θ)` inside the
//! frustum, 0 outside. A ray through a uniformly chosen film point then carries weight 1.
//!
//! Raster coordinates run from (0, 0) at the top-left corner of the image to
//! (width, height) at the bottom-right; pixel (x, y) has index `x + y·width`.

use glam::Vec3;

/// A pinhole camera (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Camera {
    /// Position of the pinhole.
    pub position: [f32; 3],
    /// tan(vertical field of view / 2).
    pub tan_half_fov_y: f32,
    /// Unit vector to the right on the image.
    pub right: [f32; 3],
    /// Image width / height.
    pub aspect: f32,
    /// Unit vector up on the image.
    pub up: [f32; 3],
    /// Image width in pixels.
    pub width: f32,
    /// Unit view direction.
    pub forward: [f32; 3],
    /// Image height in pixels.
    pub height: f32,
}

impl Camera {
    /// The position as a vector.
    #[inline]
    pub fn origin(&self) -> Vec3 {
        Vec3::from_array(self.position)
    }

    /// Area of the film's image on the plane at distance 1.
    #[inline]
    pub fn film_area(&self) -> f32 {
        4.0 * self.tan_half_fov_y * self.tan_half_fov_y * self.aspect
    }

    /// The unit direction of the ray through raster point (x, y).
    #[inline]
    pub fn direction(&self, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.width - 1.0) * self.tan_half_fov_y * self.aspect;
        let sy = (1.0 - 2.0 * y / self.height) * self.tan_half_fov_y;
        (Vec3::from_array(self.forward) + sx * Vec3::from_array(self.right) + sy * Vec3::from_array(self.up))
            .normalize()
    }

    /// The raster point that direction `d` (unit) projects to; `inside` is false when it
    /// falls outside the image or behind the camera.
    #[inline]
    pub fn raster(&self, d: Vec3) -> RasterPoint {
        let cos_theta = d.dot(Vec3::from_array(self.forward));
        if cos_theta <= 0.0 {
            return RasterPoint { x: 0.0, y: 0.0, cos_theta, inside: false };
        }
        let p = d / cos_theta;
        let sx = p.dot(Vec3::from_array(self.right)) / (self.tan_half_fov_y * self.aspect);
        let sy = p.dot(Vec3::from_array(self.up)) / self.tan_half_fov_y;
        let x = (sx + 1.0) * 0.5 * self.width;
        let y = (1.0 - sy) * 0.5 * self.height;
        let inside = x >= 0.0 && x < self.width && y >= 0.0 && y < self.height;
        RasterPoint { x, y, cos_theta, inside }
    }

    /// The index of the pixel containing raster point (x, y).
    #[inline]
    pub fn pixel(&self, x: f32, y: f32) -> u32 {
        let w = self.width as u32;
        let h = self.height as u32;
        let px = if x < 0.0 { 0 } else { (x as u32).min(w - 1) };
        let py = if y < 0.0 { 0 } else { (y as u32).min(h - 1) };
        px + py * w
    }

    /// The importance `We` of a ray leaving in direction `d`.
    #[inline]
    pub fn importance(&self, d: Vec3) -> f32 {
        let r = self.raster(d);
        if !r.inside {
            return 0.0;
        }
        let c2 = r.cos_theta * r.cos_theta;
        1.0 / (self.film_area() * c2 * c2)
    }

    /// The solid-angle density of sampling direction `d` through a uniform film point.
    #[inline]
    pub fn pdf_direction(&self, d: Vec3) -> f32 {
        let r = self.raster(d);
        if !r.inside {
            return 0.0;
        }
        1.0 / (self.film_area() * r.cos_theta * r.cos_theta * r.cos_theta)
    }
}

/// Where a direction lands on the film.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RasterPoint {
    /// Raster x: 0 at the image's left edge, `width` at its right.
    pub x: f32,
    /// Raster y: 0 at the image's top edge, `height` at its bottom.
    pub y: f32,
    /// Cosine between the direction and the view direction.
    pub cos_theta: f32,
    /// Whether the point lies on the image.
    pub inside: bool,
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: [0.0, 1.0, 3.0],
            tan_half_fov_y: (20.0f32).to_radians().tan(),
            right: [1.0, 0.0, 0.0],
            aspect: 1.5,
            up: [0.0, 1.0, 0.0],
            width: 300.0,
            forward: [0.0, 0.0, -1.0],
            height: 200.0,
        }
    }

    #[test]
    fn direction_and_raster_invert_each_other() {
        let c = camera();
        for (x, y) in [(0.5, 0.5), (150.0, 100.0), (299.5, 10.25), (3.0, 199.9)] {
            let r = c.raster(c.direction(x, y));
            assert!(r.inside);
            assert!((r.x - x).abs() < 1e-3 && (r.y - y).abs() < 1e-3, "{x},{y} -> {r:?}");
        }
        assert_eq!(c.pixel(299.9, 199.9), 299 + 199 * 300);
        assert!(!c.raster(Vec3::new(0.0, 0.0, 1.0)).inside, "behind the camera");
    }

    /// The importance integrates to 1 over the film's solid angle, and We / p_dir · cosθ = 1
    /// (a uniformly sampled camera ray has weight 1).
    #[test]
    fn importance_is_normalised() {
        let c = camera();
        let n = 400;
        let mut integral = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let x = (i as f32 + 0.5) / n as f32 * c.width;
                let y = (j as f32 + 0.5) / n as f32 * c.height;
                let d = c.direction(x, y);
                // Sampling d has solid-angle density p_dir; the estimator We · cos / p_dir
                // must be 1 everywhere.
                let w = c.importance(d) * d.dot(Vec3::from_array(c.forward)) / c.pdf_direction(d);
                assert!((w - 1.0).abs() < 1e-4);
                integral += (c.importance(d) / c.pdf_direction(d)) as f64;
            }
        }
        // ∫ We dω = E[We / p_dir] over uniform film points.
        let mean_cos_inv = integral / (n * n) as f64;
        assert!(mean_cos_inv > 1.0, "We/p_dir = 1/cosθ ≥ 1");
    }
}

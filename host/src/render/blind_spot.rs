//! The light a method cannot render in a scene. The path tracer and the path estimator
//! build every path from the camera, joining it to a light only by next-event estimation (a
//! shadow ray from a diffuse vertex) or by hitting an emitter: a path that reaches a punctual
//! light (a delta position or direction, which no ray hits) through a smooth dielectric or off
//! a smooth mirror (a delta lobe, which no shadow ray follows) — L S+ D … E, a lamp's caustic
//! through glass — has
//! no technique among theirs, so its light is missing from their images however long they
//! run. The multiplexed estimator's light subpaths start at the lamp and render it.

use super::{Estimator, Method};
use crate::scene::SceneData;

/// One line saying what `method` leaves out of `scene`'s image, or None when it renders
/// every path the scene has.
pub fn blind_spot(method: Method, scene: &SceneData) -> Option<String> {
    let camera_only =
        matches!(method, Method::PathTracer | Method::Metropolis { estimator: Estimator::Path, .. });
    let delta = scene.triangles.iter().any(|t| scene.materials[t.material as usize].has_delta_lobe());
    (camera_only && delta && !scene.punctual.is_empty()).then(|| {
        format!(
            "{method} cannot render the punctual lamps' light through smooth glass or off smooth \
             mirrors (caustics, L S+ D E paths): it is missing from this image; naive, s<d> and \
             rc<l> render it"
        )
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scenes::{generate, GltfBuilder};

    fn scene(text: &str) -> SceneData {
        SceneData::from_slice(text.as_bytes(), "test").unwrap()
    }

    /// Told exactly where a punctual lamp and smooth glass meet, for the camera-only methods.
    #[test]
    fn camera_only_methods_are_told_of_a_lamp_through_glass() {
        let caustic = scene(&generate("caustic", 1).unwrap());
        for (name, told) in [
            ("pt", true),
            ("path-naive", true),
            ("path-s3", true),
            ("naive", false),
            ("s3", false),
            ("rc4", false),
        ] {
            let line = blind_spot(name.parse().unwrap(), &caustic);
            assert_eq!(line.is_some(), told, "{name}: {line:?}");
            if let Some(line) = line {
                assert!(line.starts_with(name) && !line.contains('\n'), "{line}");
            }
        }
        // Lamps without glass, and glass under an area lamp: every path has a technique.
        let lamps = scene(&generate("lamps", 1).unwrap());
        assert_eq!(blind_spot(Method::PathTracer, &lamps), None);
        let mut b = GltfBuilder::new();
        let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 1.0, None);
        let glass = b.glass("glass", [1.0; 3], 1.5, true);
        let v = Vec3::new;
        b.quad(lamp, [v(-1., 2., -1.), v(1., 2., -1.), v(1., 2., 1.), v(-1., 2., 1.)]);
        b.sphere(glass, Vec3::ZERO, 0.5, 6);
        b.camera(v(0., 0., 3.), Vec3::ZERO, Vec3::Y, 1.0);
        assert_eq!(blind_spot(Method::PathTracer, &scene(&b.to_json())), None);
        // A lamp through rough glass: the path tracer's light samples at the glass reach it.
        let mut b = GltfBuilder::new();
        let floor = b.material("floor", [0.5; 3], [0.0; 3], 1.0, None);
        let frosted = b.glass("frosted", [1.0; 3], 1.5, true);
        b.roughness(frosted, 0.3);
        b.quad(floor, [v(-1., 0., 1.), v(1., 0., 1.), v(1., 0., -1.), v(-1., 0., -1.)]);
        b.sphere(frosted, v(0., 0.6, 0.), 0.5, 6);
        b.point_light(v(0., 2., 0.), [1.0; 3], 100.0);
        b.camera(v(0., 1., 3.), Vec3::ZERO, Vec3::Y, 1.0);
        assert_eq!(blind_spot(Method::PathTracer, &scene(&b.to_json())), None);
        // A lamp off a smooth metal is a caustic too; off a rough one, or a Lambert floor, not.
        for (roughness, told) in [(0.0, true), (0.2, false)] {
            let mut b = GltfBuilder::new();
            let floor = b.material("floor", [0.5; 3], [0.0; 3], 1.0, None);
            let metal = b.pbr("metal", [0.9; 3], 1.0, roughness);
            b.quad(floor, [v(-1., 0., 1.), v(1., 0., 1.), v(1., 0., -1.), v(-1., 0., -1.)]);
            b.sphere(metal, v(0., 0.6, 0.), 0.5, 6);
            b.point_light(v(0., 2., 0.), [1.0; 3], 100.0);
            b.camera(v(0., 1., 3.), Vec3::ZERO, Vec3::Y, 1.0);
            assert_eq!(
                blind_spot(Method::PathTracer, &scene(&b.to_json())).is_some(),
                told,
                "roughness {roughness}"
            );
        }
    }
}

//! glTF's punctual lights (`KHR_lights_punctual`) as [`PunctualLight`]s in world space.
//!
//! Units follow Blender's glTF importer (`io_import_scene_gltf2`, `PBR_WATTS_TO_LUMENS = 683`),
//! so that a scene round-tripped through Blender has Cycles' brightness: a point or spot
//! light's `intensity` in candela is a radiant intensity of `color × intensity / 683` W/sr, a
//! directional light's in lux an irradiance of `color × intensity / 683` W/m². Lights sit on
//! their nodes' world transforms and shine down the node's −Z; a node's scale changes neither
//! their brightness nor their cone, as the spec says. `range` is not modelled: the falloff is
//! the physical inverse square (said once, where a light has one).

use glam::{Mat4, Vec3, Vec4Swizzles};
use gltf::khr_lights_punctual::Kind;
use shared::punctual::PunctualLight;

use super::read::MAX_COORDINATE;
use super::SceneError;

/// Lumens per watt of the photometric units glTF's lights are given in (Blender's
/// `PBR_WATTS_TO_LUMENS`).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// The light of `node` (world transform `world`) in world space, or why it is refused: the
/// spec's ranges (a colour in [0, 1], an intensity ≥ 0, 0 ≤ inner < outer ≤ π/2) are checked
/// here, each refusal naming the light by its glTF path.
pub fn read_light(
    light: &gltf::khr_lights_punctual::Light,
    node: usize,
    world: Mat4,
    name: &str,
    warnings: &mut Vec<String>,
) -> Result<PunctualLight, SceneError> {
    let at = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}.{what}") };
    let color = light.color();
    if !color.iter().all(|c| (0.0..=1.0).contains(c)) {
        return Err(malformed(format!("color: {color:?}: each component must lie in [0, 1]")));
    }
    let intensity = light.intensity();
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(malformed(format!("intensity: {intensity}: must be a finite number ≥ 0")));
    }
    if light.range().is_some() {
        warnings.push(format!("{at}: range is ignored (smlt's lights fall off as the inverse square)"));
    }
    let radiometric = Vec3::from_array(color) * (intensity / LUMENS_PER_WATT);
    let position = (world * glam::Vec4::W).xyz();
    let direction = (world * glam::Vec4::new(0.0, 0.0, -1.0, 0.0)).xyz().normalize();
    if !(position.abs().max_element() <= MAX_COORDINATE && direction.is_finite()) {
        return Err(SceneError::Malformed {
            path: name.into(),
            what: format!(
                "nodes[{node}]: the light's world transform is degenerate or beyond ±{MAX_COORDINATE:e}"
            ),
        });
    }
    Ok(match light.kind() {
        Kind::Point => PunctualLight::point(position, radiometric),
        Kind::Directional => PunctualLight::directional(direction, radiometric, Vec3::ZERO, 0.0),
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            if !(outer_cone_angle > 0.0 && outer_cone_angle <= half_pi) {
                return Err(malformed(format!(
                    "spot.outerConeAngle: {outer_cone_angle} rad: must lie in (0, π/2]"
                )));
            }
            if !(inner_cone_angle >= 0.0 && inner_cone_angle < outer_cone_angle) {
                return Err(malformed(format!(
                    "spot.innerConeAngle: {inner_cone_angle} rad: must lie in [0, outerConeAngle = {outer_cone_angle})"
                )));
            }
            PunctualLight::spot(position, direction, radiometric, inner_cone_angle, outer_cone_angle)
        }
    })
}

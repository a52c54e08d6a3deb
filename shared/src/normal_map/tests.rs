//! The tangent frame and the bent normal against frames and normals worked by hand.

use super::*;

/// The derivatives of a triangle's points over its texture coordinates recover the affine map
/// that placed the points: p = o + u·a + v·c.
#[test]
fn position_derivatives_invert_the_texture_mapping() {
    let (o, a, c) = (Vec3::new(1.0, -2.0, 0.5), Vec3::new(0.3, 1.2, -0.4), Vec3::new(-0.7, 0.2, 0.9));
    let uvs = [Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.35), Vec2::new(0.4, 1.1)];
    let p = |uv: Vec2| (o + a * uv.x + c * uv.y).to_array();
    let tri = Triangle { v0: p(uvs[0]), v1: p(uvs[1]), v2: p(uvs[2]), ..Default::default() };
    let (dp_du, dp_dv) = position_derivatives(&tri, uvs[0], uvs[1], uvs[2]);
    assert!((dp_du - a).abs().max_element() < 1e-5, "{dp_du} {a}");
    assert!((dp_dv - c).abs().max_element() < 1e-5, "{dp_dv} {c}");
    // Coordinates along a line span no area: no frame.
    let line = [Vec2::ZERO, Vec2::new(1.0, 1.0), Vec2::new(2.0, 2.0)];
    assert_eq!(position_derivatives(&tri, line[0], line[1], line[2]), (Vec3::ZERO, Vec3::ZERO));
}

/// The spec's tangent space in a triangle's own mapping: x along dp/du, y up in the image
/// (−dp/dv, as glTF's v runs down it), z the normal; x and y times the scale; a mirrored mapping
/// turns y, not x.
#[test]
fn a_normal_texel_bends_the_normal_in_the_mappings_frame() {
    let (n, du, dv) = (Vec3::Z, Vec3::X * 2.0, Vec3::Y * 0.5);
    let texel = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * 0.5 + Vec3::splat(0.5);
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-6;
    let frame = TangentFrame::of_mapping(n, du, dv);
    assert_eq!(frame, TangentFrame { tangent: Vec3::X, bitangent: -Vec3::Y, normal: n });
    assert!(close(frame.bend(texel(0.0, 0.0, 1.0), 1.0, n), n), "the flat texel");
    assert!(close(frame.bend(texel(1.0, 0.0, 0.0), 1.0, n), Vec3::X), "+x: the tangent");
    assert!(close(frame.bend(texel(0.0, 1.0, 0.0), 1.0, n), -Vec3::Y), "+y: up, −dp/dv");
    let mirrored = TangentFrame::of_mapping(n, du, -dv);
    assert!(close(mirrored.bend(texel(0.0, 1.0, 0.0), 1.0, n), Vec3::Y), "mirrored: +y is +dp/dv");
    let tilted = frame.bend(texel(0.6, -0.6, 0.6), 0.5, n);
    assert!(close(tilted, Vec3::new(0.3, 0.3, 0.6).normalize()), "{tilted}");
    // The tangent is made orthogonal to a tilted normal; the result stays unit.
    let m = Vec3::new(0.0, 0.6, 0.8);
    let frame = TangentFrame::of_mapping(m, Vec3::new(1.0, 0.0, 0.3), dv);
    assert!(close(frame.bend(texel(0.0, 0.0, 1.0), 1.0, m), m));
    assert!((frame.bend(texel(0.5, 0.1, 0.7), 2.0, m).length() - 1.0).abs() < 1e-6);
    // No frame (no tangent off the normal, or no direction in the texel): the normal as it is.
    assert_eq!(TangentFrame::of_mapping(n, Vec3::Z, dv), TangentFrame::NONE);
    assert_eq!(TangentFrame::of_mapping(n, Vec3::ZERO, Vec3::ZERO), TangentFrame::NONE);
    assert_eq!(TangentFrame::NONE.bend(texel(1.0, 0.0, 0.0), 1.0, n), n);
    assert_eq!(TangentFrame::of_mapping(n, du, dv).bend(Vec3::splat(0.5), 1.0, n), n);
}

/// Vertex tangents interpolate like any vertex attribute, w included.
#[test]
fn vertex_tangents_interpolate_over_the_triangle() {
    let t = TriangleTangents { t: [1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, -1.0] };
    assert_eq!(t.at(Vec2::X), Vec4::new(1.0, 0.0, 0.0, 1.0));
    assert_eq!(t.at(Vec2::ZERO), Vec4::new(0.0, 0.0, 1.0, -1.0));
    assert_eq!(t.at(Vec2::new(0.5, 0.25)), Vec4::new(0.5, 0.25, 0.25, 0.5));
    assert_eq!(TriangleTangents::default().at(Vec2::new(0.3, 0.3)), Vec4::ZERO);
}

/// Vertex tangents make the frame MikkTSpace reconstructs: tangent and normal as interpolated
/// (not normalised, not orthogonal), the bitangent w (n × t), the spec's.
#[test]
fn vertex_tangents_make_mikktspaces_unnormalised_frame() {
    let texel = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * 0.5 + Vec3::splat(0.5);
    // Tangents along +y, w = +1 and −1, at the normal +z: bitangent −x and +x.
    for (w, bitangent) in [(1.0, -Vec3::X), (-1.0, Vec3::X)] {
        let frame = TangentFrame::of_vertex_tangents(Vec3::Z, Vec4::new(0.0, 1.0, 0.0, w));
        assert_eq!(frame, TangentFrame { tangent: Vec3::Y, bitangent, normal: Vec3::Z });
        assert!((frame.bend(texel(1.0, 0.0, 0.0), 1.0, Vec3::Z) - Vec3::Y).length() < 1e-6);
        assert!((frame.bend(texel(0.0, 1.0, 0.0), 1.0, Vec3::Z) - bitangent).length() < 1e-6);
    }
    // Interpolated vectors as they are: a tangent of length 0.5 leaning into a normal of
    // length 0.9 weigh the texel's x and z as MikkTSpace's sampler does.
    let (n, t) = (Vec3::new(0.0, 0.0, 0.9), Vec3::new(0.5, 0.0, 0.1));
    let frame = TangentFrame::of_vertex_tangents(n, t.extend(1.0));
    let m = Vec3::new(0.4, 0.2, 0.8);
    let want = (t * m.x + n.cross(t) * m.y + n * m.z).normalize();
    assert!((frame.bend(texel(m.x, m.y, m.z), 1.0, Vec3::Z) - want).length() < 1e-6);
    // No tangent: no frame.
    assert_eq!(TangentFrame::of_vertex_tangents(Vec3::Z, Vec4::ZERO), TangentFrame::NONE);
    assert_eq!(TangentFrame::of_vertex_tangents(Vec3::Z, Vec4::new(0.0, 0.0, 0.0, 1.0)), TangentFrame::NONE);
}

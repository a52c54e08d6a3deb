//! The material at a point against texels and factors combined by hand.

use super::*;
use crate::environment::{Environment, NONE as NO_ENVIRONMENT};
use crate::light::LightEntry;
use crate::normal_map::TriangleTangents;
use crate::normals::{Normals, TriangleNormals};
use crate::punctual::{PunctualLight, NONE as NO_PUNCTUAL};
use crate::texture::{srgb_to_linear, texture_transform, Texture, WRAP_CLAMP, WRAP_REPEAT};
use glam::Vec2;

fn rgba(r: u8, g: u8, b: u8, a: u8) -> u32 {
    u32::from_le_bytes([r, g, b, a])
}

/// Everything a scene needs besides what a test varies.
struct Fixture {
    triangles: Vec<Triangle>,
    materials: Vec<Material>,
    material_textures: Vec<MaterialTextures>,
    textures: Vec<Texture>,
    texels: Vec<u32>,
    texcoords: Vec<TriangleTexcoords>,
    normals: Vec<TriangleNormals>,
    tangents: Vec<TriangleTangents>,
    colors: Vec<TriangleColors>,
    lights: [LightEntry; 1],
    punctual: [PunctualLight; 1],
    environment: Environment,
}

impl Fixture {
    fn scene(&self) -> Scene<'_, ()> {
        Scene {
            caster: (),
            triangles: &self.triangles,
            materials: &self.materials,
            lights: &self.lights,
            punctual: &self.punctual,
            environment: &self.environment,
            environment_map: &[0.0],
            material_textures: &self.material_textures,
            textures: &self.textures,
            texels: &self.texels,
            texcoords: &self.texcoords,
            normals: &self.normals,
            tangents: &self.tangents,
            colors: &self.colors,
        }
    }
}

/// Two triangles of material 1 (textured) and 2 (not): the unit square's lower-left half at
/// z = 0 with TEXCOORD_0 = (x, y) and TEXCOORD_1 = (2x, 2y); a 2 × 2 nearest, clamped base
/// colour texture, a 1 × 1 metallic-roughness texture and a 2 × 1 repeating, bilinear emissive one.
fn fixture() -> Fixture {
    let tri = Triangle {
        v0: [0.0; 3],
        v1: [1.0, 0.0, 0.0],
        v2: [0.0, 1.0, 0.0],
        material: 1,
        ..Default::default()
    };
    let plain = Material { albedo: [0.5; 3], textures: 0, ..Default::default() };
    let textured = Material {
        albedo: [0.5, 1.0, 1.0],
        emission: [2.0, 2.0, 2.0],
        alpha: 0.25,
        metallic: 0.5,
        ior: 1.5,
        textures: 1,
        ..Default::default()
    };
    let at =
        |texture: u32, tex_coord: u32| TextureRef { texture, tex_coord, transform: crate::texture::IDENTITY };
    let texels = vec![
        // Base colour, 2 × 2: rows from the top (v = 0).
        rgba(255, 0, 0, 255),
        rgba(0, 255, 0, 255),
        rgba(128, 128, 128, 255),
        rgba(0, 0, 255, 255),
        // Metallic-roughness, 1 × 1: G roughness 128, B metal 51.
        rgba(0, 128, 51, 255),
        // Emissive, 2 × 1: black then white.
        rgba(0, 0, 0, 255),
        rgba(255, 255, 255, 255),
    ];
    Fixture {
        triangles: vec![tri, Triangle { material: 2, ..tri }],
        materials: vec![Material::default(), textured, plain],
        material_textures: vec![
            MaterialTextures::default(),
            MaterialTextures {
                base_color: at(0, 0),
                metallic_roughness: at(1, 0),
                emissive: TextureRef {
                    texture: 2,
                    tex_coord: 1,
                    transform: texture_transform([0.5, 0.0], 0.0, [1.0, 1.0]),
                },
                metallic: 0.8,
                roughness: 0.6,
                transmission_factor: 0.5,
                alpha_mode: 0,
                alpha_cutoff: 0.5,
                alpha: 1.0,
                normal: TextureRef::NONE,
                normal_scale: 1.0,
                clearcoat: TextureRef::NONE,
                clearcoat_roughness: TextureRef::NONE,
                clearcoat_factor: 0.0,
                clearcoat_roughness_factor: 0.0,
                clearcoat_normal: TextureRef::NONE,
                clearcoat_normal_scale: 1.0,
                vertex_colors: 0,
                anisotropic: 0,
                anisotropy: TextureRef::NONE,
                specular: TextureRef::NONE,
                specular_color: TextureRef::NONE,
                transmission: TextureRef::NONE,
                sheen_color: TextureRef::NONE,
                sheen_roughness: TextureRef::NONE,
            },
        ],
        textures: vec![
            Texture {
                offset: 0,
                width: 2,
                height: 2,
                sampler: Texture::sampler(WRAP_CLAMP, WRAP_CLAMP, true),
            },
            Texture {
                offset: 4,
                width: 1,
                height: 1,
                sampler: Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, false),
            },
            Texture {
                offset: 5,
                width: 2,
                height: 1,
                sampler: Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, false),
            },
        ],
        texels,
        texcoords: vec![
            TriangleTexcoords { uv: [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0] };
            2
        ],
        lights: [LightEntry { light: 0, cdf: 1.0 }],
        normals: vec![TriangleNormals::default()],
        tangents: vec![TriangleTangents::default()],
        colors: vec![TriangleColors::default()],
        punctual: [NO_PUNCTUAL],
        environment: NO_ENVIRONMENT,
    }
}

#[test]
fn barycentrics_invert_the_triangles_point() {
    let tri =
        Triangle { v0: [1.0, 2.0, 3.0], v1: [4.0, -1.0, 0.5], v2: [-2.0, 0.0, 7.0], ..Default::default() };
    for (b0, b1) in [(0.2, 0.3), (1.0, 0.0), (0.0, 0.0), (0.05, 0.9)] {
        let b = barycentrics(&tri, tri.point(b0, b1));
        assert!((b - Vec2::new(b0, b1)).abs().max_element() < 1e-5, "{b} for ({b0}, {b1})");
    }
    // A point off the plane projects onto it.
    let off = tri.point(0.2, 0.3) + tri.normal() * 0.5;
    assert!((barycentrics(&tri, off) - Vec2::new(0.2, 0.3)).abs().max_element() < 1e-5);
    let flat = Triangle { v0: [0.0; 3], v1: [1.0, 0.0, 0.0], v2: [2.0, 0.0, 0.0], ..Default::default() };
    assert_eq!(barycentrics(&flat, Vec3::ONE), Vec2::splat(1.0 / 3.0));
}

#[test]
fn a_material_without_textures_is_the_same_everywhere() {
    let f = fixture();
    let scene = f.scene();
    let p = Vec3::new(0.7, 0.1, 0.0);
    assert_eq!(material_at(&scene, 1, p), f.materials[2]);
    assert_eq!(material_at_barycentrics(&scene, 1, Vec2::new(0.2, 0.7)), f.materials[2]);
}

/// `COLOR_0` multiplies the base colour (factor × texture) where the material says so,
/// interpolated over the triangle; nothing else changes, and a material without the flag ignores
/// the colours.
#[test]
fn vertex_colors_multiply_the_base_colour() {
    let mut f = fixture();
    f.colors = vec![TriangleColors { rgb: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0] }; 2];
    let p = Vec3::new(0.7, 0.1, 0.0); // weights: v0 0.2, v1 0.7, v2 0.1
    let uncoloured = material_at(&f.scene(), 0, p);
    f.material_textures[1].vertex_colors = 1;
    let coloured = material_at(&f.scene(), 0, p);
    let expected = Vec3::from_array(uncoloured.albedo) * Vec3::new(0.2, 0.7, 0.1);
    assert!((Vec3::from_array(coloured.albedo) - expected).abs().max_element() < 1e-6, "{coloured:?}");
    assert_eq!(Material { albedo: uncoloured.albedo, ..coloured }, uncoloured);
    // The same through light sampling's barycentric lookup.
    let b = Vec2::new(0.2, 0.7);
    assert_eq!(material_at_barycentrics(&f.scene(), 0, b).albedo, coloured.albedo);
    // A material with colours and no texture: the factor times the colour.
    f.material_textures[1] = MaterialTextures { vertex_colors: 1, alpha: 1.0, ..Default::default() };
    let m = material_at(&f.scene(), 0, p);
    assert!(
        (Vec3::from_array(m.albedo) - Vec3::new(0.5, 1.0, 1.0) * Vec3::new(0.2, 0.7, 0.1))
            .abs()
            .max_element()
            < 1e-6
    );
}

#[test]
fn textures_multiply_their_factors_at_the_points_coordinates() {
    let f = fixture();
    let scene = f.scene();
    // (x, y) = (0.7, 0.1): TEXCOORD_0 (0.7, 0.1) is the base colour's texel (1, 0), green.
    let m = material_at(&scene, 0, Vec3::new(0.7, 0.1, 0.0));
    assert_eq!(m.albedo, [0.0, 1.0, 0.0]);
    // (0.2, 0.6): texel (0, 1), grey 128, sRGB-decoded to 0.2158605, times the factor.
    let g = srgb_to_linear(128.0 / 255.0);
    let grey = material_at(&scene, 0, Vec3::new(0.2, 0.6, 0.0)).albedo;
    assert!((Vec3::from_array(grey) - Vec3::new(0.5 * g, g, g)).abs().max_element() < 1e-6, "{grey:?}");
    // (0.1, 0.1): texel (0, 0), red times the factor's red 0.5.
    assert_eq!(material_at(&scene, 0, Vec3::new(0.1, 0.1, 0.0)).albedo, [0.5, 0.0, 0.0]);
    // Metallic-roughness: roughness 0.6 × 128/255, metallic 0.8 × 51/255 = 0.16 mixed with
    // transmission 0.5: glass 0.5 (1 − 0.16) = 0.42, metal share 0.16 / 0.58.
    let roughness = 0.6 * 128.0 / 255.0;
    assert!((m.alpha - roughness * roughness).abs() < 1e-6, "{}", m.alpha);
    let metal = 0.8 * 51.0 / 255.0;
    assert!((m.transmission - 0.5 * (1.0 - metal)).abs() < 1e-6, "{}", m.transmission);
    assert!((m.metallic - metal / (1.0 - 0.5 * (1.0 - metal))).abs() < 1e-6, "{}", m.metallic);
    // Emission from TEXCOORD_1 = (1.4, 0.2), offset by 0.5 to u = 1.9: repeats to 0.9, the
    // white texel; sRGB-decoded bilinear between the two texel centres at 0.25 and 0.75 and
    // wrapping: u·w − 0.5 = 1.3 → 0.7 of the white texel (1) and 0.3 of the black one (0).
    let e = m.emission[0];
    assert!((e - 2.0 * 0.7).abs() < 1e-5, "{e}");
    // Light sampling's barycentric lookup agrees with the positional one.
    let b = Vec2::new(1.0 - 0.7 - 0.1, 0.7);
    assert_eq!(material_at_barycentrics(&scene, 0, b).albedo, m.albedo);
}

/// `KHR_materials_transmission`'s transmissionTexture: the point's transmission is the factor
/// times the texel's red (linear), mixed with the point's metallic (the metallic-roughness
/// texture's) as the untextured material mixes them; without a metallic-roughness texture the
/// metallic is the factor's.
#[test]
fn a_transmission_texture_scales_the_glass_share() {
    let mut f = fixture();
    // The base colour texture's texel (1, 0), pure green at (0.7, 0.1): red 0, no glass.
    f.material_textures[1].transmission =
        TextureRef { texture: 0, tex_coord: 0, transform: crate::texture::IDENTITY };
    let p = Vec3::new(0.7, 0.1, 0.0);
    let metal = 0.8 * 51.0 / 255.0;
    let m = material_at(&f.scene(), 0, p);
    assert_eq!(m.transmission, 0.0);
    assert!((m.metallic - metal).abs() < 1e-6, "{}", m.metallic);
    // Texel (0, 1), grey 128 at (0.2, 0.6): red 128/255, read linear.
    let t = 0.5 * 128.0 / 255.0;
    let m = material_at(&f.scene(), 0, Vec3::new(0.2, 0.6, 0.0));
    assert!((m.transmission - t * (1.0 - metal)).abs() < 1e-6, "{}", m.transmission);
    assert!((m.metallic - metal / (1.0 - t * (1.0 - metal))).abs() < 1e-6, "{}", m.metallic);
    // Texel (0, 0), red 255: the factor itself.
    let m = material_at(&f.scene(), 0, Vec3::new(0.1, 0.1, 0.0));
    assert!((m.transmission - 0.5 * (1.0 - metal)).abs() < 1e-6, "{}", m.transmission);
    // Without the metallic-roughness texture the metallic is the factor's 0.8.
    f.material_textures[1].metallic_roughness = TextureRef::NONE;
    let m = material_at(&f.scene(), 0, Vec3::new(0.2, 0.6, 0.0));
    assert!((m.transmission - t * 0.2).abs() < 1e-6, "{}", m.transmission);
    assert!((m.metallic - 0.8 / (1.0 - t * 0.2)).abs() < 1e-6, "{}", m.metallic);
}

/// `KHR_materials_clearcoat`'s textures: the intensity is the factor times the clearcoat
/// texture's R, the roughness the factor times the roughness texture's G, both read linear.
#[test]
fn clearcoat_textures_multiply_their_factors() {
    let mut f = fixture();
    let at = |texture: u32| TextureRef { texture, tex_coord: 0, transform: crate::texture::IDENTITY };
    // The base colour's 2 × 2 texture as the intensity (R: 255 at texel (0, 0), 0 at (1, 0)),
    // the metallic-roughness texel (G 128) as the roughness.
    let t = &mut f.material_textures[1];
    (t.clearcoat, t.clearcoat_roughness, t.clearcoat_factor, t.clearcoat_roughness_factor) =
        (at(0), at(1), 0.8, 0.5);
    let scene = f.scene();
    let red = material_at(&scene, 0, Vec3::new(0.1, 0.1, 0.0));
    let green = material_at(&scene, 0, Vec3::new(0.7, 0.1, 0.0));
    assert_eq!((red.clearcoat, green.clearcoat), (0.8, 0.0));
    let grey = material_at(&scene, 0, Vec3::new(0.2, 0.6, 0.0));
    assert!((grey.clearcoat - 0.8 * 128.0 / 255.0).abs() < 1e-6, "linear, not sRGB: {}", grey.clearcoat);
    let roughness = 0.5 * 128.0 / 255.0;
    assert!((red.clearcoat_alpha - roughness * roughness).abs() < 1e-7, "{}", red.clearcoat_alpha);
}

#[test]
fn shading_normals_interpolate_the_vertex_normals_at_the_point() {
    let mut f = fixture();
    // Triangle 0 (v0 origin, v1 +x, v2 +y; geometric normal +z) with normals bent towards
    // each vertex's outside; triangle 1 flat (no entry).
    let s = 0.6f32.sqrt();
    let (n0, n1, n2) = (Vec3::new(-s, -s, 0.5).normalize(), Vec3::new(s, 0.0, 0.8), Vec3::new(0.0, s, 0.8));
    f.normals = vec![TriangleNormals {
        n: [n0.to_array(), n1.to_array(), n2.to_array()].concat().try_into().unwrap(),
    }];
    let scene = f.scene();
    let at_v1 = normals_at(&scene, 0, Vec3::X);
    assert_eq!(at_v1.geometric, Vec3::Z);
    assert!((at_v1.shading - n1.normalize()).length() < 1e-6, "{}", at_v1.shading);
    // At (0.25, 0.25): barycentrics (0.5, 0.25, 0.25) of v0, v1, v2.
    let want = (n0 * 0.5 + n1 * 0.25 + n2 * 0.25).normalize();
    let mid = normals_at(&scene, 0, Vec3::new(0.25, 0.25, 0.0));
    assert!((mid.shading - want).length() < 1e-6, "{} against {want}", mid.shading);
    // A triangle beyond the normals is flat.
    assert_eq!(normals_at(&scene, 1, Vec3::new(0.2, 0.2, 0.0)), Normals::flat(Vec3::Z));
}

/// A normal texture added to the fixture: 2 × 1 texels, nearest, read on TEXCOORD_1 (= 2 (x,
/// y)) scaled by 1/2, so that left of x = 0.5 (u' < 0.5) the texel leans to +x and right of it
/// to +y (up in the image: −dp/dv', here −y).
fn leaning_texture(f: &mut Fixture) -> TextureRef {
    let first = f.texels.len() as u32;
    f.texels.extend([rgba(255, 128, 128, 255), rgba(128, 255, 128, 255)]);
    f.textures.push(Texture {
        offset: first,
        width: 2,
        height: 1,
        sampler: Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, true),
    });
    let scaled = texture_transform([0.0, 0.0], 0.0, [0.5, 0.5]);
    TextureRef { texture: f.textures.len() as u32 - 1, tex_coord: 1, transform: scaled }
}

/// A material's normal texture bends the shading normal of its triangles at the point's
/// coordinates (through the texture's own set and transform), the geometric normal stays, and a
/// material without one keeps the flat normal.
#[test]
fn the_normal_texture_bends_the_shading_normal() {
    let mut f = fixture();
    f.material_textures[1].normal = leaning_texture(&mut f);
    f.material_textures[1].normal_scale = 0.5;
    let scene = f.scene();
    let c = 128.0 / 255.0 * 2.0 - 1.0;
    // (0.2, 0.1): u' = 0.5 · 2 · 0.2 = 0.2, the left texel; (0.7, 0.1): u' = 0.7, the right.
    let left = normals_at(&scene, 0, Vec3::new(0.2, 0.1, 0.0));
    let right = normals_at(&scene, 0, Vec3::new(0.7, 0.1, 0.0));
    assert_eq!(left.geometric, Vec3::Z);
    assert!((left.shading - Vec3::new(0.5, -0.5 * c, c).normalize()).abs().max_element() < 1e-6, "{left:?}");
    assert!(
        (right.shading - Vec3::new(0.5 * c, -0.5, c).normalize()).abs().max_element() < 1e-6,
        "{right:?}"
    );
    assert_eq!(normals_at(&scene, 1, Vec3::new(0.2, 0.1, 0.0)), Normals::flat(Vec3::Z));
}

/// The clear coat's normal: unbent where only the base has a normal texture, bent by its own
/// clearcoatNormalTexture (and scale) in the same frame where it has one, and the shading
/// normal where the material has neither.
#[test]
fn the_coat_normal_is_bent_by_its_own_texture_only() {
    let mut f = fixture();
    let texture = leaning_texture(&mut f);
    let c = 128.0 / 255.0 * 2.0 - 1.0;
    let left = Vec3::new(0.2, 0.1, 0.0);
    let leaning = Vec3::new(0.5, -0.5 * c, c).normalize();
    // The base's normal texture alone: the coat stays flat.
    f.material_textures[1].normal = texture;
    f.material_textures[1].normal_scale = 0.5;
    let n = normals_at(&f.scene(), 0, left);
    assert!((n.shading - leaning).abs().max_element() < 1e-6 && n.coat == Vec3::Z, "{n:?}");
    // The coat's own texture alone (the frame from its coordinates): the shading stays flat.
    f.material_textures[1].normal = TextureRef::NONE;
    f.material_textures[1].clearcoat_normal = texture;
    f.material_textures[1].clearcoat_normal_scale = 0.5;
    let n = normals_at(&f.scene(), 0, left);
    assert!((n.coat - leaning).abs().max_element() < 1e-6 && n.shading == Vec3::Z, "{n:?}");
    // Both, each with its scale.
    f.material_textures[1].normal = texture;
    f.material_textures[1].normal_scale = 1.0;
    let n = normals_at(&f.scene(), 0, left);
    assert!((n.coat - leaning).abs().max_element() < 1e-6, "{n:?}");
    assert!((n.shading - Vec3::new(1.0, -c, c).normalize()).abs().max_element() < 1e-6, "{n:?}");
    // Neither: the coat's normal is the shading one.
    assert_eq!(normals_at(&f.scene(), 1, left), Normals::flat(Vec3::Z));
}

/// Where a triangle has vertex tangents the normal texture bends the normal in their frame,
/// not in its coordinates' own.
#[test]
fn vertex_tangents_set_the_normal_textures_frame() {
    let mut f = fixture();
    // A 1 × 1 texture on TEXCOORD_0 whose texel leans fully to +x.
    let first = f.texels.len() as u32;
    f.texels.push(rgba(255, 128, 128, 255));
    f.textures.push(Texture {
        offset: first,
        width: 1,
        height: 1,
        sampler: Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, false),
    });
    f.material_textures[1].normal =
        TextureRef { texture: 3, tex_coord: 0, transform: crate::texture::IDENTITY };
    let p = Vec3::new(0.2, 0.1, 0.0);
    let c = 128.0 / 255.0 * 2.0 - 1.0;
    let mapped = normals_at(&f.scene(), 0, p).shading;
    assert!((mapped - Vec3::new(1.0, -c, c).normalize()).abs().max_element() < 1e-6, "{mapped}");
    // Tangents along +y (w = −1: the bitangent −(n × t) = +x): the texel's +x leans to +y.
    let along_y = [0.0, 1.0, 0.0, -1.0];
    f.tangents = vec![TriangleTangents { t: [along_y, along_y, along_y].concat().try_into().unwrap() }];
    let bent = normals_at(&f.scene(), 0, p).shading;
    assert!((bent - Vec3::new(c, 1.0, c).normalize()).abs().max_element() < 1e-6, "{bent}");
}

/// The anisotropy's direction: the texel's 2·rg − 1 (unit or not) turned by the factor's angle,
/// whatever the factor's length (the strength); zero where either gives no direction.
#[test]
fn anisotropy_direction_turns_the_texel_by_the_rotation() {
    let factor = Vec2::new(0.5f32.cos(), 0.5f32.sin()) * 0.6;
    let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-6;
    assert!(close(anisotropy_direction(factor, Vec2::new(1.0, 0.5)), Vec2::new(0.5f32.cos(), 0.5f32.sin())));
    let quarter = 0.5 + core::f32::consts::FRAC_PI_2;
    assert!(close(
        anisotropy_direction(factor, Vec2::new(0.5, 0.9)),
        Vec2::new(quarter.cos(), quarter.sin())
    ));
    let diagonal = 0.5 - core::f32::consts::FRAC_PI_4 * 3.0;
    let d = anisotropy_direction(factor, Vec2::new(0.1, 0.1));
    assert!(close(d, Vec2::new(diagonal.cos(), diagonal.sin())), "{d}");
    assert_eq!(anisotropy_direction(factor, Vec2::splat(0.5)), Vec2::ZERO);
    assert_eq!(anisotropy_direction(Vec2::ZERO, Vec2::new(1.0, 0.5)), Vec2::ZERO);
}

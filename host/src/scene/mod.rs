//! Scenes: loading glTF 2.0 into the flat buffers the passes use (triangles in BVH order, the
//! compressed wide BVH from obvhs, materials, the light CDF) and the camera.
//!
//! What is read, and nothing more (model only what a scene needs):
//! - triangle meshes (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN: `primitive`; points and lines
//!   are skipped with a warning) with node
//!   transforms, matrix or TRS, of the default scene (or the first), and their vertex normals
//!   (`NORMAL`, the shading normals: `shared::normals`; without them a mesh is flat, as the
//!   spec says); attributes as floats or as `KHR_mesh_quantization`'s integers (`attributes`),
//!   their views compressed or not (`EXT_meshopt_compression`: `meshopt`), or the whole
//!   primitive one Draco stream (`KHR_draco_mesh_compression`: `draco`);
//! - materials: glTF's metallic-roughness BRDF (`baseColorFactor`, `metallicFactor`,
//!   `roughnessFactor`, `KHR_materials_specular`, `KHR_materials_ior`), glass
//!   (`KHR_materials_transmission` with its texture, `_volume`), the clear coat
//!   (`KHR_materials_clearcoat`, its textures and normal texture, read from the JSON: `read`);
//!   `emissiveFactor` × `KHR_materials_emissive_strength` → emission (one-sided, along the
//!   triangle's counter-clockwise normal); the Phong exponent from the material's extras, key
//!   [`PHONG_EXPONENT_KEY`] (absent or 0: the BRDF); base colour, metallic-roughness,
//!   emissive and normal textures (`textures`; PNG, JPEG, WebP with `EXT_texture_webp`, KTX2
//!   with `KHR_texture_basisu`), a normal texture in the mesh's `TANGENT`s or MikkTSpace's
//!   (`tangents`); vertex colours, `COLOR_0`, times the base colour (`colors`); morph targets
//!   at their weights (`morph`); skinned meshes in the pose their
//!   joints hold (`skin`); each primitive read once and placed as often as its node draws it
//!   (`primitive`: instances of `EXT_mesh_gpu_instancing` in `instancing`). Other material
//!   extensions and textures change the image but are not modelled: each is named in a printed
//!   warning;
//! - punctual lights (`KHR_lights_punctual`: point, spot, directional) on their nodes, in
//!   Blender's units (`lights`);
//! - cameras, in the order of a depth-first walk of the scene: the views `--view N` names,
//!   the first perspective one rendered without `--view` (each node looks down −Z with +Y up;
//!   the image aspect comes from the render's width/height). smlt's camera is a pinhole: an
//!   orthographic camera is named in a warning and refused as a view, not as a file (Blender's
//!   exporter writes every camera of the scene). Without a perspective camera, the documented
//!   default: a 40° vertical field of view looking down −Z at the centre of the scene's bounding
//!   box, from where the box's larger side fills the view.
//!
//! Besides the file, a render may be given an environment light (`--environment`,
//! [`EnvironmentSpec`]): it is picked with the file's lights, its light subpaths start on the
//! same bounding sphere's disks as a directional light's.

mod attributes;
mod colors;
mod draco;
mod environment;
mod instancing;
mod ktx2;
mod lights;
mod meshopt;
mod morph;
mod parse;
mod primitive;
mod read;
mod skin;
mod tangents;
mod textures;
mod validate;

pub use environment::EnvironmentSpec;
pub use lights::LUMENS_PER_WATT;
pub use read::{files_hash, read_document, PHONG_EXPONENT_KEY};
pub use textures::Source;

use glam::Vec3;
use obvhs::cwbvh::CwBvh;
use shared::bsdf::Material;
use shared::camera::Camera;
use shared::color::luminance;
use shared::cutout::Cutouts;
use shared::cwbvh::{WideBvh, WideNode, WIDE_BVH_STACK_SIZE};
use shared::environment::{Environment, EnvironmentMap};
use shared::light::{light_cdf, LightEntry, ENVIRONMENT, PUNCTUAL};
use shared::normal_map::TriangleTangents;
use shared::normals::TriangleNormals;
use shared::punctual::PunctualLight;
use shared::scene::Scene;
use shared::surface::{MaterialTextures, TriangleColors, TriangleTexcoords};
use shared::texture::{Texture, TextureRef};
use shared::triangle::{Triangle, TriangleEdges};

use std::sync::{Arc, OnceLock};

use crate::caster::{EmbreeCaster, EmbreeScene, HostCaster, ObvhsCaster};

/// Why a scene could not be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file is missing or unreadable, or not valid glTF.
    #[error("cannot load glTF scene {path}: {reason}")]
    Load {
        /// The scene's name for messages: its file path, or a built-in scene's name.
        path: String,
        /// The gltf crate's reason.
        reason: String,
    },
    /// Something the renderer does not model and that would make the image wrong.
    #[error("unsupported glTF content in {path}: {what}")]
    Unsupported {
        /// The scene's name for messages: its file path, or a built-in scene's name.
        path: String,
        /// The unsupported content, in words.
        what: String,
    },
    /// The file breaks the glTF specification (an accessor past its buffer view, a camera's
    /// field of view out of range, …): `what` names the element by its glTF path.
    #[error("malformed glTF {path}: {what}")]
    Malformed {
        #[allow(missing_docs)] // the scene's path
        path: String,
        #[allow(missing_docs)] // the element and what is wrong with it
        what: String,
    },
    /// No triangles at all.
    #[error("scene {0} has no triangles")]
    Empty(String),
    /// No emitting triangle of positive area, no punctual light of positive power and no
    /// environment light that is not black.
    #[error(
        "nothing emits light in scene {0}: give some material an emissiveFactor, add a KHR_lights_punctual light, or light it with --environment"
    )]
    NoEmitter(String),
    /// The environment light cannot be used (`--environment`).
    #[error("cannot use environment {given}: {what}")]
    Environment {
        /// The file or colour given.
        given: String,
        /// What is wrong with it.
        what: String,
    },
    /// The BVH is deeper than the device traversal stack.
    #[error("the BVH of scene {path} is {depth} levels deep; traversal supports {max}")]
    BvhTooDeep {
        /// The scene's name for messages: its file path, or a built-in scene's name.
        path: String,
        /// The BVH's depth in levels.
        depth: usize,
        /// The deepest BVH the traversal supports ([`WIDE_BVH_STACK_SIZE`]).
        max: usize,
    },
}

/// Where the camera is and where it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    /// Pinhole position.
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit up direction (orthogonal to forward).
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub yfov: f32,
    /// The glTF camera's aspect ratio (width / height), when it states one: `--height`
    /// defaults to the width divided by it.
    pub aspect: Option<f32>,
}

/// One of the file's cameras: a view `--view` may name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// A perspective camera: rendered.
    Perspective(CameraSpec),
    /// An orthographic camera, glTF's `cameras[camera]`: named, not rendered (smlt's camera is a
    /// pinhole).
    Orthographic {
        #[allow(missing_docs)]
        camera: usize,
    },
}

/// A scene ready for rendering.
#[derive(Clone, Debug)]
pub struct SceneData {
    /// Where it came from (for messages).
    pub name: String,
    /// Triangles in BVH order.
    pub triangles: Vec<Triangle>,
    /// The compressed wide BVH over `triangles` (nodes root first; its primitive order is the
    /// triangles' order).
    pub bvh: CwBvh,
    /// The triangles' vertices and edges, in the same order: what obvhs's caster reads, made on
    /// its first use (Embree, where it is used, keeps its own copy).
    pub edges: OnceLock<Vec<TriangleEdges>>,
    /// Embree's scene of the triangles, built on the CPU backend's first use where Embree is
    /// used (None where it is not).
    pub embree: OnceLock<Option<Arc<EmbreeScene>>>,
    /// Indexed by `Triangle::material`.
    pub materials: Vec<Material>,
    /// The light-selection CDF over the emissive triangles and the punctual lights.
    pub lights: Vec<LightEntry>,
    /// The punctual lights (`KHR_lights_punctual`), in world space; a directional light's disk
    /// covers the bounding sphere of `bounds`.
    pub punctual: Vec<PunctualLight>,
    /// The environment light (`shared::environment::NONE` without one), its disk the same
    /// sphere's and its pick the light CDF's.
    pub environment: Environment,
    /// Its texels and CDFs (one zero without one: a device buffer is never empty).
    pub environment_map: Vec<f32>,
    /// Indexed by `Material::textures` (entry 0 unused).
    pub material_textures: Vec<MaterialTextures>,
    /// The textures (one zeroed entry without any).
    pub textures: Vec<Texture>,
    /// Their texels, RGBA8 (one zero without any).
    pub texels: Vec<u32>,
    /// Per triangle in `triangles`' order where any material has textures; one zeroed entry
    /// otherwise.
    pub texcoords: Vec<TriangleTexcoords>,
    /// Per triangle in `triangles`' order where any triangle has smooth normals; one zeroed
    /// (flat) entry otherwise.
    pub normals: Vec<TriangleNormals>,
    /// Per triangle in `triangles`' order where any triangle has vertex tangents (a normal
    /// texture's, `shared::normal_map`); one zeroed entry otherwise.
    pub tangents: Vec<TriangleTangents>,
    /// Per triangle in `triangles`' order where any material has vertex colours
    /// (`MaterialTextures::vertex_colors`); one zeroed entry otherwise.
    pub colors: Vec<TriangleColors>,
    /// The camera of the selected view.
    pub camera: CameraSpec,
    /// Every camera of the file, in scene order (views 1, 2, …).
    pub views: Vec<View>,
    /// Bounding box of all triangles.
    pub bounds: (Vec3, Vec3),
    /// Things the renderer ignored that change the image.
    pub warnings: Vec<String>,
}

/// A triangle mesh before the BVH: world-space triangles with their materials.
#[derive(Clone, Debug, Default)]
pub struct TriangleSoup {
    /// Vertices (world space), three per triangle.
    pub triangles: Vec<[Vec3; 3]>,
    /// Material of each triangle.
    pub material_of: Vec<u32>,
    /// Indexed by `material_of`.
    pub materials: Vec<Material>,
    /// Indexed by `Material::textures` (entry 0 unused; empty where no material has textures).
    pub material_textures: Vec<MaterialTextures>,
    /// The textures the materials read.
    pub textures: Vec<Texture>,
    /// Their texels (`shared::texture`).
    pub texels: Vec<u32>,
    /// Texture coordinates of each triangle (zeros where its material has no textures; empty:
    /// none anywhere).
    pub texcoords: Vec<TriangleTexcoords>,
    /// Vertex normals of each triangle, up to the last smooth one (zeros where it is flat;
    /// empty: none anywhere).
    pub normals: Vec<TriangleNormals>,
    /// Vertex tangents of each triangle, up to the last one that has them (zeros where it has
    /// none; empty: none anywhere).
    pub tangents: Vec<TriangleTangents>,
    /// Vertex colours (`COLOR_0`) of each triangle, up to the last one whose material has them
    /// (zeros where it has none; empty: none anywhere).
    pub colors: Vec<TriangleColors>,
    /// The file's punctual lights in world space (a directional light's centre and radius are
    /// set from the scene's bounds when the scene is built).
    pub punctual: Vec<PunctualLight>,
    /// The file's cameras, in scene order.
    pub cameras: Vec<View>,
    /// The environment light the render was given (not the file's: glTF has none).
    pub environment: Option<EnvironmentMap>,
    /// Ignored content.
    pub warnings: Vec<String>,
}

impl SceneData {
    /// The scene as the kernel bodies take it on the CPU backend: ray queries through the
    /// host's fastest caster (`crate::caster`).
    pub fn shared(&self) -> Scene<'_, HostCaster<'_>> {
        let embree = self.embree.get_or_init(|| {
            crate::caster::wants_embree()
                .then(|| EmbreeScene::new(&self.triangles, self.cutouts()).ok().map(Arc::new))
                .flatten()
        });
        match embree {
            Some(e) => {
                self.with_caster(HostCaster::Embree(EmbreeCaster { scene: e, cutouts: self.cutouts() }))
            }
            None => self.obvhs_view(),
        }
    }

    /// The cut-outs every caster lets rays through (`shared::cutout`).
    pub fn cutouts(&self) -> Cutouts<'_> {
        Cutouts {
            triangles: &self.triangles,
            materials: &self.materials,
            material_textures: &self.material_textures,
            texcoords: &self.texcoords,
            textures: &self.textures,
            texels: &self.texels,
        }
    }

    /// The scene with ray queries through obvhs's traversal of the device's BVH.
    pub fn obvhs_view(&self) -> Scene<'_, HostCaster<'_>> {
        let edges = self.edges.get_or_init(|| self.triangles.iter().map(TriangleEdges::of).collect());
        self.with_caster(HostCaster::Obvhs(ObvhsCaster { bvh: &self.bvh, edges, cutouts: self.cutouts() }))
    }

    /// The scene as the device sees it: ray queries through the shared wide-BVH traversal (on
    /// the host, for the difftests and the ray test).
    pub fn device_view(&self) -> Scene<'_, WideBvh<'_>> {
        self.with_caster(WideBvh {
            nodes: self.wide_nodes(),
            triangles: &self.triangles,
            cutouts: self.cutouts(),
        })
    }

    /// The scene over another ray caster.
    pub fn with_caster<R>(&self, caster: R) -> Scene<'_, R> {
        Scene {
            caster,
            triangles: &self.triangles,
            materials: &self.materials,
            lights: &self.lights,
            punctual: self.punctual_lights(),
            environment: &self.environment,
            environment_map: &self.environment_map,
            material_textures: &self.material_textures,
            textures: &self.textures,
            texels: &self.texels,
            texcoords: &self.texcoords,
            normals: &self.normals,
            tangents: &self.tangents,
            colors: &self.colors,
        }
    }

    /// The punctual lights as the kernels bind them: at least one entry (a zeroed one, which no
    /// light entry refers to, when the scene has none).
    pub fn punctual_lights(&self) -> &[PunctualLight] {
        static NONE: [PunctualLight; 1] = [shared::punctual::NONE];
        if self.punctual.is_empty() {
            &NONE
        } else {
            &self.punctual
        }
    }

    /// The BVH's nodes as the device's [`WideNode`]s (the same bytes).
    pub fn wide_nodes(&self) -> &[WideNode] {
        bytemuck::cast_slice(&self.bvh.nodes)
    }

    /// The device camera for an image of `width` × `height`.
    pub fn camera(&self, width: u32, height: u32) -> Camera {
        let c = self.camera;
        let right = c.forward.cross(c.up).normalize();
        Camera {
            position: c.position.to_array(),
            tan_half_fov_y: (c.yfov * 0.5).tan(),
            right: right.to_array(),
            aspect: width as f32 / height as f32,
            up: right.cross(c.forward).normalize().to_array(),
            width: width as f32,
            forward: c.forward.to_array(),
            height: height as f32,
        }
    }

    /// The view a render without `--view` sees: the first perspective camera's number (1-based);
    /// 1 for a file without cameras (view 1 is then the default framing, as `select_view` takes
    /// it); 0 for the default framing of a file whose cameras are all orthographic.
    pub fn default_view(&self) -> u32 {
        if self.views.is_empty() {
            return 1;
        }
        self.views.iter().position(|v| matches!(v, View::Perspective(_))).map_or(0, |i| i as u32 + 1)
    }

    /// Selects view `view` (1-based) among the file's cameras (without it, the scene's camera is
    /// its first perspective one, or the default framing).
    pub fn select_view(&mut self, view: u32) -> Result<(), SceneError> {
        if view == 1 && self.views.is_empty() {
            return Ok(()); // the default camera
        }
        let refuse = |what: String| SceneError::Unsupported { path: self.name.clone(), what };
        match self.views.get(view.wrapping_sub(1) as usize) {
            Some(View::Perspective(c)) => {
                self.camera = *c;
                Ok(())
            }
            Some(View::Orthographic { camera }) => Err(refuse(format!(
                "view {view} is cameras[{camera}], an orthographic camera; smlt renders perspective cameras"
            ))),
            None => Err(refuse(format!(
                "view {view} requested, but the scene has {} camera(s)",
                self.views.len()
            ))),
        }
    }

    /// What the scene holds, in words for the render summary: its triangles (how many are
    /// smooth, how many have vertex tangents for a normal texture or an anisotropic lobe, how
    /// many vertex colours, how many are anisotropic) and, where it has any, its textures and
    /// the memory of their texels.
    pub fn describe_contents(&self) -> String {
        let smooth = self.normals.iter().filter(|n| **n != TriangleNormals::default()).count();
        let tangents = self.tangents.iter().filter(|t| **t != TriangleTangents::default()).count();
        let entry = |t: &shared::triangle::Triangle| {
            self.material_textures[self.materials[t.material as usize].textures as usize]
        };
        let coloured = self.triangles.iter().filter(|t| entry(t).vertex_colors != 0).count();
        let anisotropic = self.triangles.iter().filter(|t| entry(t).anisotropic != 0).count();
        let mut text = format!("{} triangles", self.triangles.len());
        let counts: Vec<String> = [
            (smooth, "with smooth normals"),
            (tangents, "with vertex tangents"),
            (coloured, "with vertex colours"),
            (anisotropic, "anisotropic"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
        if !counts.is_empty() {
            text += &format!(" ({})", counts.join(", "));
        }
        let textures = self
            .material_textures
            .iter()
            .skip(1)
            .filter(|t| t.slots().iter().any(TextureRef::is_some))
            .count();
        if textures > 0 {
            text += &format!(
                ", {} textured material(s) reading {} texture(s) ({:.1} MiB of texels)",
                textures,
                self.textures.len(),
                (self.texels.len() * 4) as f64 / 1048576.0
            );
        }
        text
    }

    /// Ray-origin offset relative to the scene's size.
    pub fn epsilon(&self) -> f32 {
        1e-5 * (self.bounds.1 - self.bounds.0).max_element().max(1e-3)
    }

    /// Builds the BVH, orders the triangles by it, and builds the light CDF.
    pub fn from_soup(soup: TriangleSoup, name: &str) -> Result<Self, SceneError> {
        if soup.triangles.is_empty() {
            return Err(SceneError::Empty(name.into()));
        }
        let tris: Vec<obvhs::triangle::Triangle> = soup
            .triangles
            .iter()
            .map(|t| obvhs::triangle::Triangle { v0: t[0].into(), v1: t[1].into(), v2: t[2].into() })
            .collect();
        let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
            &tris,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let depth = bvh_depth(&bvh);
        if depth > WIDE_BVH_STACK_SIZE {
            return Err(SceneError::BvhTooDeep { path: name.into(), depth, max: WIDE_BVH_STACK_SIZE });
        }
        debug_assert_eq!(bvh.primitive_indices.len(), tris.len(), "no spatial splits: one slot a triangle");
        let mut triangles: Vec<Triangle> = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let [a, b, c] = soup.triangles[i as usize];
                Triangle {
                    v0: a.to_array(),
                    material: soup.material_of[i as usize],
                    v1: b.to_array(),
                    light_area_pdf: 0.0,
                    v2: c.to_array(),
                    area: 0.5 * (b - a).cross(c - a).length(),
                }
            })
            .collect();
        let mut lo = Vec3::splat(f32::MAX);
        let mut hi = Vec3::splat(f32::MIN);
        for t in &soup.triangles {
            for v in t {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        // A directional light's disk, and the environment's, cover the bounding sphere of the
        // triangles.
        let (centre, radius) = ((lo + hi) * 0.5, (0.5 * (hi - lo).length()).max(1e-3));
        let mut punctual = soup.punctual;
        for light in punctual.iter_mut().filter(|l| l.is_directional()) {
            light.position = centre.to_array();
            light.radius = radius;
        }
        // Triangles and punctual lights on one scale of power (`shared::light`).
        let mut power: Vec<f64> = triangles
            .iter()
            .map(|t| {
                let e = Vec3::from_array(soup.materials[t.material as usize].emission);
                (luminance(e) as f64 * t.area as f64).max(0.0)
            })
            .collect();
        let mut area: Vec<f32> = triangles.iter().map(|t| t.area).collect();
        let mut ids: Vec<u32> = (0..triangles.len() as u32).collect();
        for (i, light) in punctual.iter().enumerate() {
            power.push(light.selection_power() as f64);
            area.push(1.0);
            ids.push(PUNCTUAL | i as u32);
        }
        // The environment's flux through its disk over π: r² ∫ luminance(L) dω.
        if let Some(env) = &soup.environment {
            power.push(radius as f64 * radius as f64 * env.luminance_integral());
            area.push(1.0);
            ids.push(ENVIRONMENT);
        }
        let (lights, pdf) =
            light_cdf(&power, &area, &ids).ok_or_else(|| SceneError::NoEmitter(name.into()))?;
        let (environment, environment_map) = match soup.environment {
            Some(env) => {
                let e = Environment {
                    pick: *pdf.last().expect("the environment's entry"),
                    centre: centre.to_array(),
                    radius,
                    ..env.environment
                };
                (e, env.map)
            }
            None => (shared::environment::NONE, vec![0.0]),
        };
        for (t, pdf) in triangles.iter_mut().zip(pdf) {
            t.light_area_pdf = pdf;
        }
        let camera = soup
            .cameras
            .iter()
            .find_map(|v| match v {
                View::Perspective(c) => Some(*c),
                View::Orthographic { .. } => None,
            })
            .unwrap_or_else(|| default_camera(lo, hi));
        // Texture coordinates in the BVH's order, where a material reads them; every texture
        // buffer holds at least one element.
        let textured = soup.materials.iter().any(|m| m.textures != 0);
        let texcoords = if textured && soup.texcoords.len() == soup.triangles.len() {
            bvh.primitive_indices.iter().map(|&i| soup.texcoords[i as usize]).collect()
        } else {
            vec![TriangleTexcoords::default()]
        };
        // Vertex normals likewise, where any triangle is smooth.
        let smooth = soup.normals.iter().any(|n| *n != TriangleNormals::default());
        let normals = if smooth {
            // The loader stores normals up to the last smooth triangle: the rest are flat.
            bvh.primitive_indices
                .iter()
                .map(|&i| soup.normals.get(i as usize).copied().unwrap_or_default())
                .collect()
        } else {
            vec![TriangleNormals::default()]
        };
        // Vertex tangents likewise, where any triangle has them.
        let tangents = if soup.tangents.iter().any(|t| *t != TriangleTangents::default()) {
            bvh.primitive_indices
                .iter()
                .map(|&i| soup.tangents.get(i as usize).copied().unwrap_or_default())
                .collect()
        } else {
            vec![TriangleTangents::default()]
        };
        // Vertex colours likewise, where any material has them.
        let colors = if soup.colors.is_empty() {
            vec![TriangleColors::default()]
        } else {
            bvh.primitive_indices
                .iter()
                .map(|&i| soup.colors.get(i as usize).copied().unwrap_or_default())
                .collect()
        };
        let mut material_textures = soup.material_textures;
        if material_textures.is_empty() {
            material_textures.push(MaterialTextures::default());
        }
        let textures = if soup.textures.is_empty() { vec![Texture::default()] } else { soup.textures };
        let texels = if soup.texels.is_empty() { vec![0] } else { soup.texels };
        Ok(SceneData {
            name: name.into(),
            triangles,
            edges: OnceLock::new(),
            embree: OnceLock::new(),
            bvh,
            materials: soup.materials,
            lights,
            punctual,
            environment,
            environment_map,
            material_textures,
            textures,
            texels,
            texcoords,
            normals,
            tangents,
            colors,
            camera,
            views: soup.cameras,
            bounds: (lo, hi),
            warnings: soup.warnings,
        })
    }
}

/// The documented default camera: 40° vertical field of view, looking down −Z at the box's
/// centre from where its larger side fills the view.
pub fn default_camera(lo: Vec3, hi: Vec3) -> CameraSpec {
    let yfov = 40f32.to_radians();
    let centre = (lo + hi) * 0.5;
    let extent = hi - lo;
    let distance = 0.5 * extent.x.max(extent.y) / (yfov * 0.5).tan() + 0.5 * extent.z;
    CameraSpec {
        position: centre + Vec3::Z * distance.max(1e-3),
        forward: -Vec3::Z,
        up: Vec3::Y,
        yfov,
        aspect: None,
    }
}

/// Depth (levels of nodes) of a compressed wide BVH: the traversal stack holds at most one
/// entry a level.
fn bvh_depth(bvh: &CwBvh) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((i, depth)) = stack.pop() {
        deepest = deepest.max(depth);
        let node = &bvh.nodes[i];
        for child in 0..8 {
            if !node.is_leaf(child) {
                stack.push((node.child_node_index(child) as usize, depth + 1));
            }
        }
    }
    deepest
}

//! Scenes: loading glTF 2.0 into the flat buffers the passes use (triangles in BVH order, BVH
//! nodes from obvhs, materials, the light CDF) and the camera.
//!
//! What is read, and nothing more (model only what a scene needs):
//! - triangle meshes (primitive mode TRIANGLES; any other mode is an error) with node
//!   transforms, matrix or TRS, of the default scene (or the first);
//! - materials: `baseColorFactor` → albedo; `emissiveFactor` × `KHR_materials_emissive_strength`
//!   → emission (one-sided, along the triangle's counter-clockwise normal); the Phong exponent
//!   from the material's extras, key [`PHONG_EXPONENT_KEY`] (absent or 0: Lambertian).
//!   Textures and other material extensions change the image but are not modelled: each is
//!   named in a printed warning;
//! - perspective cameras, in the order of a depth-first walk of the scene: view 1 is the first
//!   (`--view N` picks another; each node looks down −Z with +Y up; the image aspect comes from
//!   the render's width/height). Without one, the documented default: a 40° vertical field of
//!   view looking down −Z at the centre of the scene's bounding box, from where the box's
//!   larger side fills the view.

use std::path::Path;

use glam::{Mat4, Vec3, Vec4Swizzles};
use shared::bsdf::Material;
use shared::bvh::{BvhNode, Triangle, BVH_STACK_SIZE};
use shared::camera::Camera;
use shared::light::{light_cdf, LightEntry};
use shared::mmlt::luminance;

/// The material-extras key holding the Phong exponent, e.g. `"extras": {"smlt_phong_exponent": 1e5}`.
pub const PHONG_EXPONENT_KEY: &str = "smlt_phong_exponent";

/// Why a scene could not be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file is missing or unreadable, or not valid glTF.
    #[error("cannot load glTF scene {path}: {reason}")]
    Load {
        /// The scene path.
        path: String,
        /// The gltf crate's reason.
        reason: String,
    },
    /// Something the renderer does not model and that would make the image wrong.
    #[error("unsupported glTF content in {path}: {what}")]
    Unsupported {
        /// The scene path.
        path: String,
        /// What.
        what: String,
    },
    /// No triangles at all.
    #[error("scene {0} has no triangles")]
    Empty(String),
    /// No emitting triangle of positive area.
    #[error("nothing emits light in scene {0}: give some material an emissiveFactor")]
    NoEmitter(String),
    /// The BVH is deeper than the device traversal stack.
    #[error("the BVH of scene {path} is {depth} levels deep; traversal supports {max}")]
    BvhTooDeep {
        /// The scene path.
        path: String,
        /// Its depth.
        depth: usize,
        /// The limit.
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

/// A scene ready for rendering.
#[derive(Clone, Debug)]
pub struct SceneData {
    /// Where it came from (for messages).
    pub name: String,
    /// Triangles in BVH order.
    pub triangles: Vec<Triangle>,
    /// BVH nodes (root first).
    pub nodes: Vec<BvhNode>,
    /// Materials.
    pub materials: Vec<Material>,
    /// The light-selection CDF over emissive triangles.
    pub lights: Vec<LightEntry>,
    /// The camera of the selected view.
    pub camera: CameraSpec,
    /// Every perspective camera of the file, in scene order (views 1, 2, …).
    pub views: Vec<CameraSpec>,
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
    /// Materials.
    pub materials: Vec<Material>,
    /// The file's perspective cameras, in scene order.
    pub cameras: Vec<CameraSpec>,
    /// Ignored content.
    pub warnings: Vec<String>,
}

impl SceneData {
    /// The scene as the kernel bodies take it.
    pub fn shared(&self) -> shared::mmlt::Scene<'_> {
        shared::mmlt::Scene {
            nodes: &self.nodes,
            triangles: &self.triangles,
            materials: &self.materials,
            lights: &self.lights,
        }
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

    /// Selects view `view` (1-based) among the file's cameras.
    pub fn select_view(&mut self, view: u32) -> Result<(), SceneError> {
        if view == 1 && self.views.is_empty() {
            return Ok(()); // the default camera
        }
        match self.views.get(view.wrapping_sub(1) as usize) {
            Some(c) => {
                self.camera = *c;
                Ok(())
            }
            None => Err(SceneError::Unsupported {
                path: self.name.clone(),
                what: format!("view {view} requested, but the scene has {} camera(s)", self.views.len()),
            }),
        }
    }

    /// Ray-origin offset relative to the scene's size.
    pub fn epsilon(&self) -> f32 {
        1e-5 * (self.bounds.1 - self.bounds.0).max_element().max(1e-3)
    }

    /// Loads a glTF (.gltf or .glb) file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let name = path.display().to_string();
        if path.is_dir() {
            return Err(SceneError::Load { path: name, reason: "is a directory, not a glTF file".into() });
        }
        let (doc, buffers, _images) = gltf::import(path).map_err(|e| {
            let reason = match (&e, missing_resource(path)) {
                (gltf::Error::Io(_), Some(uri)) => format!("the file it refers to, '{uri}', does not exist"),
                _ => e.to_string(),
            };
            SceneError::Load { path: name.clone(), reason }
        })?;
        let soup = read_document(&doc, &buffers, &name)?;
        Self::from_soup(soup, &name)
    }

    /// Loads a glTF document held in memory (a .gltf with data URIs, or a .glb).
    pub fn from_slice(bytes: &[u8], name: &str) -> Result<Self, SceneError> {
        let (doc, buffers, _images) = gltf::import_slice(bytes)
            .map_err(|e| SceneError::Load { path: name.into(), reason: e.to_string() })?;
        let soup = read_document(&doc, &buffers, name)?;
        Self::from_soup(soup, name)
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
        let bvh = obvhs::bvh2::builder::build_bvh2_from_tris(
            &tris,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let nodes: Vec<BvhNode> = bvh
            .nodes
            .iter()
            .map(|n| BvhNode {
                min: Vec3::from(n.aabb().min).to_array(),
                count: n.prim_count,
                max: Vec3::from(n.aabb().max).to_array(),
                first: n.first_index,
            })
            .collect();
        let depth = bvh_depth(&nodes);
        if depth > BVH_STACK_SIZE {
            return Err(SceneError::BvhTooDeep { path: name.into(), depth, max: BVH_STACK_SIZE });
        }
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
        let power: Vec<f64> = triangles
            .iter()
            .map(|t| {
                let e = Vec3::from_array(soup.materials[t.material as usize].emission);
                (luminance(e) as f64 * t.area as f64).max(0.0)
            })
            .collect();
        let area: Vec<f32> = triangles.iter().map(|t| t.area).collect();
        let (lights, pdf) = light_cdf(&power, &area).ok_or_else(|| SceneError::NoEmitter(name.into()))?;
        for (t, pdf) in triangles.iter_mut().zip(pdf) {
            t.light_area_pdf = pdf;
        }
        let mut lo = Vec3::splat(f32::MAX);
        let mut hi = Vec3::splat(f32::MIN);
        for t in &soup.triangles {
            for v in t {
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
        }
        let camera = soup.cameras.first().copied().unwrap_or_else(|| default_camera(lo, hi));
        Ok(SceneData {
            name: name.into(),
            triangles,
            nodes,
            materials: soup.materials,
            lights,
            camera,
            views: soup.cameras,
            bounds: (lo, hi),
            warnings: soup.warnings,
        })
    }
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
    let images = gltf.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri.to_string()),
        gltf::image::Source::View { .. } => None,
    });
    buffers.chain(images).find(|uri| !uri.starts_with("data:") && !dir.join(uri).exists())
}

/// A hash of a glTF file and every external buffer it refers to (what a cache or a part file
/// must change with: a changed `.bin` changes the scene).
pub fn files_hash(path: &Path) -> Result<String, SceneError> {
    let fail = |reason: String| SceneError::Load { path: path.display().to_string(), reason };
    let mut bytes = std::fs::read(path).map_err(|e| fail(e.to_string()))?;
    if let Ok(gltf) = gltf::Gltf::from_slice(&bytes) {
        let dir = path.parent().unwrap_or(Path::new("."));
        let uris: Vec<String> = gltf
            .buffers()
            .filter_map(|b| match b.source() {
                gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => Some(uri.to_string()),
                _ => None,
            })
            .collect();
        for uri in uris {
            bytes.extend(std::fs::read(dir.join(&uri)).map_err(|e| fail(format!("{uri}: {e}")))?);
        }
    }
    Ok(crate::reference::content_hash(&bytes))
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

/// Depth (levels) of a BVH in obvhs's layout.
fn bvh_depth(nodes: &[BvhNode]) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0u32, 1usize)];
    while let Some((i, d)) = stack.pop() {
        deepest = deepest.max(d);
        let n = nodes[i as usize];
        if n.count == 0 {
            stack.push((n.first, d + 1));
            stack.push((n.first + 1, d + 1));
        }
    }
    deepest
}

fn read_material(m: &gltf::Material, warnings: &mut Vec<String>, name: &str) -> Result<Material, SceneError> {
    let label =
        m.name().map(|n| format!("material '{n}'")).unwrap_or_else(|| format!("material {:?}", m.index()));
    let pbr = m.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    if pbr.base_color_texture().is_some() || m.emissive_texture().is_some() || m.normal_texture().is_some() {
        warnings.push(format!("{label}: textures are ignored (only factors are modelled)"));
    }
    let strength = m.emissive_strength().unwrap_or(1.0);
    let e = m.emissive_factor();
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
    Ok(Material {
        albedo: [base[0], base[1], base[2]],
        phong_exponent: phong,
        emission: [e[0] * strength, e[1] * strength, e[2] * strength],
        _pad: 0.0,
    })
}

/// Reads the triangles, materials and camera of a glTF document.
pub fn read_document(
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    name: &str,
) -> Result<TriangleSoup, SceneError> {
    let mut soup = TriangleSoup::default();
    for ext in doc.extensions_used() {
        if ext != "KHR_materials_emissive_strength" {
            soup.warnings.push(format!("extension {ext} is ignored"));
        }
    }
    // Material 0 is glTF's default material (white Lambert); document materials follow.
    soup.materials.push(Material { albedo: [1.0; 3], ..Default::default() });
    for m in doc.materials() {
        let mat = read_material(&m, &mut soup.warnings, name)?;
        soup.materials.push(mat);
    }
    let scene =
        doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| SceneError::Empty(name.into()))?;
    // glTF's node hierarchy is a set of disjoint trees: a node reached twice has two parents or
    // is its own ancestor, and a walk through a cycle would never end.
    let mut reached = vec![false; doc.nodes().len()];
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
        if let Some(cam) = node.camera() {
            {
                match cam.projection() {
                    gltf::camera::Projection::Perspective(p) => {
                        let forward = (world * glam::Vec4::new(0.0, 0.0, -1.0, 0.0)).xyz().normalize();
                        let up = (world * glam::Vec4::new(0.0, 1.0, 0.0, 0.0)).xyz().normalize();
                        soup.cameras.push(CameraSpec {
                            position: (world * glam::Vec4::W).xyz(),
                            forward,
                            up: (up - forward * up.dot(forward)).normalize(),
                            yfov: p.yfov(),
                            aspect: p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0),
                        });
                    }
                    gltf::camera::Projection::Orthographic(_) => {
                        return Err(SceneError::Unsupported {
                            path: name.into(),
                            what: "orthographic cameras are not supported (use a perspective camera)".into(),
                        });
                    }
                }
            }
        }
        if let Some(mesh) = node.mesh() {
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
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let positions: Vec<Vec3> = reader
                    .read_positions()
                    .ok_or_else(|| SceneError::Unsupported {
                        path: name.into(),
                        what: format!("mesh {} has a primitive without POSITION", mesh.index()),
                    })?
                    .map(|p| world.transform_point3(Vec3::from_array(p)))
                    .collect();
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                let material = prim.material().index().map(|i| i as u32 + 1).unwrap_or(0);
                let (triples, _) = indices.as_chunks::<3>();
                for tri in triples {
                    let mut v = [Vec3::ZERO; 3];
                    for (k, &i) in tri.iter().enumerate() {
                        v[k] = *positions.get(i as usize).ok_or_else(|| SceneError::Unsupported {
                            path: name.into(),
                            what: format!("mesh {} indexes vertex {i} of {}", mesh.index(), positions.len()),
                        })?;
                    }
                    // A mirroring transform flips the winding; keep the normal's sense.
                    if world.determinant() < 0.0 {
                        v.swap(1, 2);
                    }
                    soup.triangles.push(v);
                    soup.material_of.push(material);
                }
            }
        }
        let children: Vec<_> = node.children().map(|c| (c, world, Some(node.index()))).collect();
        stack.extend(children.into_iter().rev());
    }
    Ok(soup)
}

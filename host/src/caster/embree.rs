//! Intel Embree 3 as a ray caster, loaded at run time (`libembree3.so.3`, Debian's
//! `libembree3-3`), so that smlt builds and runs without it and uses it where it is installed.
//! Only what a static triangle scene needs is declared: a device, one triangle geometry, one
//! committed scene, and the single-ray closest-hit and occlusion queries (`rtcIntersect1`,
//! `rtcOccluded1`), which Embree documents as safe to call from many threads at once.
//!
//! Semantics against smlt's (`shared::triangle::TriangleEdges::intersect`): Embree reports
//! both faces (Debian builds it without back-face culling); it accepts tnear < t ≤ tfar, so the
//! interval's end is passed as the largest float below tmax; triangles whose edges' cross
//! product is exactly zero (which smlt never hits) are left out of its geometry, and its
//! primitive ids map back to smlt's slots. Cut-out triangles (`shared::cutout`) are a second
//! geometry with intersection and occlusion filter functions that ask
//! `shared::cutout::Cutouts::stops` (passed in an extended query context, as Embree's
//! tutorials pass user data), so opaque triangles pay nothing for them. Its triangle test
//! rounds differently (an
//! approximate reciprocal), so t may differ from the other casters' in the last bits and a ray
//! through a shared edge may pick the neighbour: `tests/ray_casters.rs` counts both.

use std::ffi::{c_char, c_void};
use std::sync::OnceLock;

use glam::Vec3;
use shared::cutout::Cutouts;
use shared::ray_caster::{Hit, NO_HIT};

use super::Query;
use shared::triangle::{Triangle, TriangleEdges};

type Handle = *mut c_void;
type FilterFunction = unsafe extern "C" fn(*const FilterArguments);

#[repr(C, align(16))]
#[derive(Clone, Copy, Default)]
struct Ray {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
#[derive(Clone, Copy, Default)]
struct HitRecord {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C)]
#[derive(Clone, Copy, Default)]
struct RayHit {
    ray: Ray,
    hit: HitRecord,
}

/// Lanes of a ray packet ([`EmbreeCaster::closest_hits`]).
pub const PACKET: usize = 16;

/// A packet query's mask: −1 for a lane to cast, 0 for one to leave; aligned as Embree wants it.
#[repr(C, align(64))]
struct Valid([i32; PACKET]);

/// `RTCRay16`: a packet of rays (SoA, each field a lane array), what `rtcOccluded16` takes.
#[repr(C, align(64))]
#[derive(Clone, Copy)]
struct Ray16 {
    org: [[f32; PACKET]; 3],
    tnear: [f32; PACKET],
    dir: [[f32; PACKET]; 3],
    time: [f32; PACKET],
    tfar: [f32; PACKET],
    mask: [u32; PACKET],
    id: [u32; PACKET],
    flags: [u32; PACKET],
}

/// `RTCHit16`: a packet's hits (SoA).
#[repr(C, align(64))]
#[derive(Clone, Copy)]
struct Hit16 {
    ng: [[f32; PACKET]; 3],
    u: [f32; PACKET],
    v: [f32; PACKET],
    prim_id: [u32; PACKET],
    geom_id: [u32; PACKET],
    inst_id: [u32; PACKET],
}

/// `RTCRayHit16`: a packet of rays and their hits, what `rtcIntersect16` takes.
#[repr(C, align(64))]
#[derive(Clone, Copy)]
struct RayHit16 {
    ray: Ray16,
    hit: Hit16,
}

// Embree's layouts: 12 and 8 lane arrays of 64 bytes.
const _: () = assert!(std::mem::size_of::<Ray16>() == 768 && std::mem::size_of::<RayHit16>() == 1280);

impl Ray16 {
    /// The packet of up to [`PACKET`] queries, and its lane mask: a lane Embree would not take
    /// (and a lane past the queries) is left out.
    fn of(queries: &[Query]) -> (Ray16, Valid) {
        let mut packet = Ray16 {
            org: [[0.0; PACKET]; 3],
            tnear: [0.0; PACKET],
            dir: [[0.0; PACKET]; 3],
            time: [0.0; PACKET],
            tfar: [0.0; PACKET],
            mask: [u32::MAX; PACKET],
            id: [0; PACKET],
            flags: [0; PACKET],
        };
        let mut valid = Valid([0; PACKET]);
        for (lane, q) in queries.iter().enumerate().take(PACKET) {
            if !EmbreeScene::takes(q.origin, q.direction, q.tmin, q.tmax) {
                continue;
            }
            valid.0[lane] = -1;
            for axis in 0..3 {
                packet.org[axis][lane] = q.origin[axis];
                packet.dir[axis][lane] = q.direction[axis];
            }
            packet.tnear[lane] = q.tmin;
            // Embree accepts t = tfar; smlt's intervals are open.
            packet.tfar[lane] = q.tmax.next_down();
        }
        (packet, valid)
    }
}

#[repr(C)]
struct IntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

/// Embree's context extended with what the cut-out filter reads: Embree hands the filter the
/// pointer the query was given.
#[repr(C)]
struct QueryContext<'a> {
    embree: IntersectContext,
    cutouts: &'a Cutouts<'a>,
    /// smlt's slot of each primitive of the cut-out geometry.
    slots: &'a [u32],
    /// The query's key for its BLEND draws (one ray a query: `rtcIntersect1`/`rtcOccluded1`).
    key: u32,
}

/// `RTCFilterFunctionNArguments`: the candidate hits of N rays (SoA), and a valid flag each.
#[repr(C)]
struct FilterArguments {
    valid: *mut i32,
    geometry_user: *mut c_void,
    context: *const QueryContext<'static>,
    ray: *mut f32,
    hit: *mut u32,
    n: u32,
}

const INVALID_ID: u32 = u32::MAX;
const GEOMETRY_TYPE_TRIANGLE: u32 = 0;
const BUFFER_TYPE_INDEX: u32 = 0;
const BUFFER_TYPE_VERTEX: u32 = 1;
const FORMAT_UINT3: u32 = 0x5003;
const FORMAT_FLOAT3: u32 = 0x9003;
const BUILD_QUALITY_HIGH: u32 = 2;

/// The entry points of the library, resolved once.
struct Api {
    new_device: unsafe extern "C" fn(*const c_char) -> Handle,
    device_error: unsafe extern "C" fn(Handle) -> u32,
    new_scene: unsafe extern "C" fn(Handle) -> Handle,
    set_build_quality: unsafe extern "C" fn(Handle, u32),
    new_geometry: unsafe extern "C" fn(Handle, u32) -> Handle,
    new_geometry_buffer: unsafe extern "C" fn(Handle, u32, u32, u32, usize, usize) -> *mut c_void,
    commit_geometry: unsafe extern "C" fn(Handle),
    attach_geometry: unsafe extern "C" fn(Handle, Handle) -> u32,
    set_intersect_filter: unsafe extern "C" fn(Handle, Option<FilterFunction>),
    set_occluded_filter: unsafe extern "C" fn(Handle, Option<FilterFunction>),
    release_geometry: unsafe extern "C" fn(Handle),
    commit_scene: unsafe extern "C" fn(Handle),
    release_scene: unsafe extern "C" fn(Handle),
    release_device: unsafe extern "C" fn(Handle),
    intersect1: unsafe extern "C" fn(Handle, *mut IntersectContext, *mut RayHit),
    occluded1: unsafe extern "C" fn(Handle, *mut IntersectContext, *mut Ray),
    intersect16: unsafe extern "C" fn(*const i32, Handle, *mut IntersectContext, *mut RayHit16),
    occluded16: unsafe extern "C" fn(*const i32, Handle, *mut IntersectContext, *mut Ray16),
    /// Keeps the library mapped while the entry points are used.
    _library: libloading::Library,
}

impl Api {
    /// The library's entry points, or why it is not there.
    fn load() -> Result<Api, String> {
        // SAFETY: loading Embree runs its (and TBB's) initialisers, which have no preconditions;
        // each symbol is read with the signature of Embree 3's C API (rtcore_*.h).
        unsafe {
            let library = libloading::Library::new("libembree3.so.3").map_err(|e| e.to_string())?;
            macro_rules! entry {
                ($name:literal) => {
                    *library.get(concat!($name, "\0").as_bytes()).map_err(|e| format!("{}: {e}", $name))?
                };
            }
            Ok(Api {
                new_device: entry!("rtcNewDevice"),
                device_error: entry!("rtcGetDeviceError"),
                new_scene: entry!("rtcNewScene"),
                set_build_quality: entry!("rtcSetSceneBuildQuality"),
                new_geometry: entry!("rtcNewGeometry"),
                new_geometry_buffer: entry!("rtcSetNewGeometryBuffer"),
                commit_geometry: entry!("rtcCommitGeometry"),
                attach_geometry: entry!("rtcAttachGeometry"),
                set_intersect_filter: entry!("rtcSetGeometryIntersectFilterFunction"),
                set_occluded_filter: entry!("rtcSetGeometryOccludedFilterFunction"),
                release_geometry: entry!("rtcReleaseGeometry"),
                commit_scene: entry!("rtcCommitScene"),
                release_scene: entry!("rtcReleaseScene"),
                release_device: entry!("rtcReleaseDevice"),
                intersect1: entry!("rtcIntersect1"),
                occluded1: entry!("rtcOccluded1"),
                intersect16: entry!("rtcIntersect16"),
                occluded16: entry!("rtcOccluded16"),
                _library: library,
            })
        }
    }

    /// The process's Embree, loaded on first use.
    fn get() -> Result<&'static Api, &'static str> {
        static API: OnceLock<Result<Api, String>> = OnceLock::new();
        API.get_or_init(Api::load).as_ref().map_err(String::as_str)
    }
}

/// Whether Embree can be used here, or why not.
pub fn available() -> Result<(), &'static str> {
    Api::get().map(|_| ())
}

/// A committed Embree scene of a scene's triangles.
pub struct EmbreeScene {
    api: &'static Api,
    device: Handle,
    scene: Handle,
    /// smlt's triangle slot of each Embree primitive: of the opaque geometry (0), then of the
    /// cut-out one (1; empty when the scene has none).
    slots: [Vec<u32>; 2],
}

// SAFETY: a committed scene is never modified again, and Embree documents concurrent ray
// queries on it from any thread as safe; the handles are released only on drop.
unsafe impl Send for EmbreeScene {}
unsafe impl Sync for EmbreeScene {}

impl std::fmt::Debug for EmbreeScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "EmbreeScene({} triangles, {} cut-outs)", self.slots[0].len(), self.slots[1].len())
    }
}

impl EmbreeScene {
    /// Builds Embree's BVH over `triangles` (the scene's, in slot order), those that
    /// `cutouts` says are cut-outs in a geometry of their own with the cut-out filters.
    pub fn new(triangles: &[Triangle], cutouts: Cutouts) -> Result<Self, String> {
        let api = Api::get()?;
        let mut slots = [Vec::new(), Vec::new()];
        for i in 0..triangles.len() as u32 {
            let e = TriangleEdges::of(&triangles[i as usize]);
            if e.e1.cross(e.e2) != Vec3::ZERO {
                slots[cutouts.is_cutout(i) as usize].push(i);
            }
        }
        // SAFETY: every call follows Embree 3's API: the buffers Embree allocates are filled
        // with exactly the item counts and strides they were created with before the geometry
        // is committed; every handle is released once.
        unsafe {
            let device = (api.new_device)(c"".as_ptr());
            if device.is_null() {
                return Err("Embree could not create a device".into());
            }
            let scene = (api.new_scene)(device);
            (api.set_build_quality)(scene, BUILD_QUALITY_HIGH);
            for (id, geometry_slots) in slots.iter().enumerate() {
                if id == 1 && geometry_slots.is_empty() {
                    break;
                }
                let geometry = (api.new_geometry)(device, GEOMETRY_TYPE_TRIANGLE);
                let n = geometry_slots.len().max(1);
                let vertices =
                    (api.new_geometry_buffer)(geometry, BUFFER_TYPE_VERTEX, 0, FORMAT_FLOAT3, 12, n * 3)
                        as *mut [f32; 3];
                let indices = (api.new_geometry_buffer)(geometry, BUFFER_TYPE_INDEX, 0, FORMAT_UINT3, 12, n)
                    as *mut [u32; 3];
                if vertices.is_null() || indices.is_null() {
                    (api.release_geometry)(geometry);
                    (api.release_scene)(scene);
                    (api.release_device)(device);
                    return Err("Embree could not allocate the scene's buffers".into());
                }
                for (k, &slot) in geometry_slots.iter().enumerate() {
                    let t = &triangles[slot as usize];
                    *vertices.add(3 * k) = t.v0;
                    *vertices.add(3 * k + 1) = t.v1;
                    *vertices.add(3 * k + 2) = t.v2;
                    *indices.add(k) = [3 * k as u32, 3 * k as u32 + 1, 3 * k as u32 + 2];
                }
                if geometry_slots.is_empty() {
                    // One triangle far away that nothing reaches (Embree wants no empty buffers).
                    *vertices = [f32::MAX; 3];
                    *vertices.add(1) = [f32::MAX; 3];
                    *vertices.add(2) = [f32::MAX; 3];
                    *indices = [0, 1, 2];
                }
                if id == 1 {
                    (api.set_intersect_filter)(geometry, Some(cutout_filter));
                    (api.set_occluded_filter)(geometry, Some(cutout_filter));
                }
                (api.commit_geometry)(geometry);
                let attached = (api.attach_geometry)(scene, geometry);
                (api.release_geometry)(geometry);
                if attached != id as u32 {
                    (api.release_scene)(scene);
                    (api.release_device)(device);
                    return Err(format!("Embree numbered geometry {id} as {attached}"));
                }
            }
            (api.commit_scene)(scene);
            let error = (api.device_error)(device);
            if error != 0 {
                (api.release_scene)(scene);
                (api.release_device)(device);
                return Err(format!("Embree failed to build the scene (error {error})"));
            }
            Ok(Self { api, device, scene, slots })
        }
    }

    fn ray(o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Ray {
        // Embree accepts t = tfar; smlt's intervals are open.
        Ray {
            org: o.to_array(),
            tnear: tmin,
            dir: d.to_array(),
            tfar: tmax.next_down(),
            mask: u32::MAX,
            ..Default::default()
        }
    }

    /// Whether Embree takes the ray: finite, within its ±1.8e18, tmin ≥ 0 and below tmax (a
    /// ray it would not take hits nothing, as smlt's NaN rays do; its debug builds abort on one).
    #[inline]
    fn takes(o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
        const LARGE: f32 = 1e18;
        o.abs().max_element() <= LARGE && d.abs().max_element() <= LARGE && tmin >= 0.0 && tmin < tmax
    }
}

/// Embree's filter of candidate hits on cut-out triangles: a hit the cut-out does not stop is
/// made invalid, and Embree traverses on. Embree sets a candidate's distance as its ray's tfar
/// before it calls the filter (and restores it if the hit is rejected).
///
/// # Safety
/// Called by Embree only, with arguments laid out as `RTCFilterFunctionNArguments` for the
/// queries of [`EmbreeCaster`], whose context is a [`QueryContext`].
unsafe extern "C" fn cutout_filter(args: *const FilterArguments) {
    // SAFETY: Embree's arguments: N rays and hits in SoA layout (RTCRayN, RTCHitN) and a valid
    // flag each; the context is the query's own (a QueryContext, alive for the query).
    unsafe {
        let args = &*args;
        let context = &*args.context;
        let n = args.n as usize;
        let ray = |field: usize, i: usize| *args.ray.add(field * n + i);
        for i in 0..n {
            if *args.valid.add(i) == 0 {
                continue;
            }
            let o = Vec3::new(ray(0, i), ray(1, i), ray(2, i));
            let d = Vec3::new(ray(4, i), ray(5, i), ray(6, i));
            let t = ray(8, i);
            let primitive = *args.hit.add(5 * n + i) as usize;
            let Some(&slot) = context.slots.get(primitive) else { continue };
            if !context.cutouts.stops(slot, o, d, t, context.key) {
                *args.valid.add(i) = 0;
            }
        }
    }
}

/// Embree's queries on a scene, with the scene's cut-outs.
#[derive(Clone, Copy)]
pub struct EmbreeCaster<'a> {
    /// The committed scene.
    pub scene: &'a EmbreeScene,
    /// The cut-outs its filters ask.
    pub cutouts: Cutouts<'a>,
}

impl EmbreeCaster<'_> {
    fn context<'c>(&'c self, key: u32) -> QueryContext<'c> {
        QueryContext {
            embree: IntersectContext { flags: 0, filter: std::ptr::null(), inst_id: [INVALID_ID] },
            cutouts: &self.cutouts,
            slots: &self.scene.slots[1],
            key,
        }
    }

    /// The closest hit in (tmin, tmax), BLEND cut-outs drawn by `key`.
    #[inline]
    pub fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        if !EmbreeScene::takes(o, d, tmin, tmax) {
            return Hit { t: NO_HIT, triangle: 0 };
        }
        let mut rayhit = RayHit { ray: EmbreeScene::ray(o, d, tmin, tmax), hit: HitRecord::default() };
        rayhit.hit.geom_id = INVALID_ID;
        rayhit.hit.prim_id = INVALID_ID;
        let mut context = self.context(key);
        let scene = self.scene;
        // SAFETY: a committed scene, a context that begins with Embree's and a ray hit laid out
        // as Embree's.
        unsafe { (scene.api.intersect1)(scene.scene, &mut context.embree, &mut rayhit) };
        match scene.slots.get(rayhit.hit.geom_id as usize) {
            Some(slots) => Hit { t: rayhit.ray.tfar, triangle: slots[rayhit.hit.prim_id as usize] },
            None => Hit { t: NO_HIT, triangle: 0 },
        }
    }

    /// The closest hits of `queries`, each in its (tmin, tmax), into `hits`: 16 at a time
    /// through Embree's packet traversal (`rtcIntersect16`), the packet's lanes independent rays
    /// of as many paths (`host/examples/rays.rs` measures it against single rays). A scene with cut-outs, whose filter reads one key a query, is
    /// cast one ray at a time; a ray Embree would not take hits nothing, as in
    /// [`EmbreeCaster::closest_hit`].
    pub fn closest_hits(&self, queries: &[Query], hits: &mut [Hit]) {
        if !self.scene.slots[1].is_empty() {
            for (q, h) in queries.iter().zip(hits.iter_mut()) {
                *h = self.closest_hit(q.origin, q.direction, q.tmin, q.tmax, q.key);
            }
            return;
        }
        let scene = self.scene;
        for (queries, hits) in queries.chunks(PACKET).zip(hits.chunks_mut(PACKET)) {
            let (ray, valid) = Ray16::of(queries);
            let hit = Hit16 {
                ng: [[0.0; PACKET]; 3],
                u: [0.0; PACKET],
                v: [0.0; PACKET],
                prim_id: [INVALID_ID; PACKET],
                geom_id: [INVALID_ID; PACKET],
                inst_id: [INVALID_ID; PACKET],
            };
            let mut packet = RayHit16 { ray, hit };
            let mut context = self.context(0);
            // SAFETY: a committed scene, a context that begins with Embree's, a lane mask and a
            // packet, each laid out and aligned (64 bytes) as Embree's; invalid lanes are not
            // read.
            unsafe {
                (scene.api.intersect16)(valid.0.as_ptr(), scene.scene, &mut context.embree, &mut packet)
            };
            for (lane, h) in hits.iter_mut().enumerate() {
                *h = match scene.slots.get(packet.hit.geom_id[lane] as usize) {
                    Some(slots) if valid.0[lane] != 0 => {
                        Hit { t: packet.ray.tfar[lane], triangle: slots[packet.hit.prim_id[lane] as usize] }
                    }
                    _ => Hit { t: NO_HIT, triangle: 0 },
                };
            }
        }
    }

    /// Whether anything blocks each of `queries` in its (tmin, tmax), into `blocked`: 16 at a time
    /// through `rtcOccluded16`, as [`EmbreeCaster::closest_hits`] casts.
    pub fn occluded_all(&self, queries: &[Query], blocked: &mut [bool]) {
        if !self.scene.slots[1].is_empty() {
            for (q, b) in queries.iter().zip(blocked.iter_mut()) {
                *b = self.occluded(q.origin, q.direction, q.tmin, q.tmax, q.key);
            }
            return;
        }
        let scene = self.scene;
        for (queries, blocked) in queries.chunks(PACKET).zip(blocked.chunks_mut(PACKET)) {
            let (mut packet, valid) = Ray16::of(queries);
            let mut context = self.context(0);
            // SAFETY: as for closest_hits; Embree sets a blocked lane's tfar to −∞.
            unsafe {
                (scene.api.occluded16)(valid.0.as_ptr(), scene.scene, &mut context.embree, &mut packet)
            };
            for (lane, b) in blocked.iter_mut().enumerate() {
                *b = valid.0[lane] != 0 && packet.tfar[lane] == f32::NEG_INFINITY;
            }
        }
    }

    /// Whether anything blocks the ray in (tmin, tmax), BLEND cut-outs drawn by `key`.
    #[inline]
    pub fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        if !EmbreeScene::takes(o, d, tmin, tmax) {
            return false;
        }
        let mut ray = EmbreeScene::ray(o, d, tmin, tmax);
        let mut context = self.context(key);
        let scene = self.scene;
        // SAFETY: as for closest_hit; Embree sets tfar to −∞ when the ray is blocked.
        unsafe { (scene.api.occluded1)(scene.scene, &mut context.embree, &mut ray) };
        ray.tfar == f32::NEG_INFINITY
    }
}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        // SAFETY: the handles were created by this scene and are released once.
        unsafe {
            (self.api.release_scene)(self.scene);
            (self.api.release_device)(self.device);
        }
    }
}

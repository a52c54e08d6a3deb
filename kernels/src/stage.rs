//! One declaration per stage: [`stage!`] turns a stage's list of bindings into everything that
//! names them —
//! - the stage's `Io` struct, the one argument of its body (slices on both sides);
//! - the `#[spirv(compute)]` entry point, whose numbered bindings unpack into that struct;
//! - `BINDINGS`, the list the host binds device buffers by (by name, with each element type,
//!   checked against the buffer it finds);
//! - `Io::from_bound`, the struct taken by name from a backend's [`Bound`] buffers, and
//!   `Io::run`, the body over invocations `0..n` in order (the CPU backend's call).
//!
//! Adding a buffer to a stage is one line in its declaration: the entry point, the device's
//! binding list and the CPU call all follow from it. Adding a buffer the render does not have
//! yet adds it to [`Bound`] and to each backend's allocation as well (the compiler and the
//! host's binding-list test say where).
//!
//! A macro rather than a build step or a proc-macro crate: macro_rules runs inside rust-gpu's
//! own compilation with nothing more to build, and the declaration stays beside the body it
//! feeds. Binding numbers are written out (`#[spirv(binding = N)]` takes a literal): they
//! count 0, 1, 2, … in order, which `tests::every_declaration_numbers_its_bindings_in_order`
//! (in `lib.rs`) checks, so a buffer inserted in the middle renumbers the ones after it.

use shared::mmlt::{ChainState, PathInfo, PathVertex};
use shared::params::RenderParams;
use shared::scene::Scene;
use spirv_std::glam::Vec4;

/// How a stage uses a storage buffer it binds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// One value, read (binding `&[T]`, element 0).
    Uniform,
    /// Read only.
    Read,
    /// Written (and maybe read).
    Write,
}

impl Access {
    /// Whether the kernel only reads the buffer.
    pub fn read_only(self) -> bool {
        !matches!(self, Access::Write)
    }
}

/// One storage buffer a stage binds.
#[derive(Clone, Copy, Debug)]
pub struct Binding {
    /// Descriptor set: 0 for the stage's own buffers, [`SCENE_SET`] for the scene's.
    pub set: u32,
    /// Binding number within the set.
    pub binding: u32,
    /// Its name: the `Io` field, the [`Bound`] field and the device buffer it is bound to.
    pub name: &'static str,
    #[allow(missing_docs)] // how the kernel uses it
    pub access: Access,
    /// `core::any::type_name` of its element.
    pub element: fn() -> &'static str,
}

/// One kernel of the module as its declaration gives it.
#[derive(Clone, Copy, Debug)]
pub struct Kernel {
    #[allow(missing_docs)] // its name in the module
    pub entry_point: &'static str,
    /// Its own bindings, set 0.
    pub bindings: &'static [Binding],
    /// Whether it binds [`SCENE_BINDINGS`] in [`SCENE_SET`] too.
    pub binds_scene: bool,
}

impl Kernel {
    #[allow(missing_docs)] // the fields
    pub const fn of(entry_point: &'static str, bindings: &'static [Binding], binds_scene: bool) -> Self {
        Self { entry_point, bindings, binds_scene }
    }

    /// Every binding as (set, binding, whether the kernel writes it), in set and binding order.
    #[cfg(not(target_arch = "spirv"))]
    pub fn interface(&self) -> std::vec::Vec<(u32, u32, bool)> {
        let scene: &[Binding] = if self.binds_scene { SCENE_BINDINGS } else { &[] };
        self.bindings.iter().chain(scene).map(|b| (b.set, b.binding, !b.access.read_only())).collect()
    }
}

/// The descriptor set of the scene's buffers (every stage that binds the scene binds the same
/// ones: a backend builds it once).
pub const SCENE_SET: u32 = 1;

/// The scene's bindings in [`SCENE_SET`], in binding order: what the entry point of a stage
/// with a scene unpacks into `shared::scene::Scene` over the device's wide BVH.
pub const SCENE_BINDINGS: &[Binding] = &[
    scene_binding(0, "nodes", core::any::type_name::<shared::cwbvh::WideNode>),
    scene_binding(1, "triangles", core::any::type_name::<shared::triangle::Triangle>),
    scene_binding(2, "materials", core::any::type_name::<shared::bsdf::Material>),
    scene_binding(3, "lights", core::any::type_name::<shared::light::LightEntry>),
    scene_binding(4, "punctual", core::any::type_name::<shared::punctual::PunctualLight>),
    scene_binding(5, "environment", core::any::type_name::<shared::environment::Environment>),
    scene_binding(6, "environment_map", core::any::type_name::<f32>),
    scene_binding(7, "material_textures", core::any::type_name::<shared::surface::MaterialTextures>),
    scene_binding(8, "textures", core::any::type_name::<shared::texture::Texture>),
    scene_binding(9, "texels", core::any::type_name::<u32>),
    scene_binding(10, "texcoords", core::any::type_name::<shared::surface::TriangleTexcoords>),
    scene_binding(11, "normals", core::any::type_name::<shared::normals::TriangleNormals>),
    scene_binding(12, "tangents", core::any::type_name::<shared::normal_map::TriangleTangents>),
    scene_binding(13, "colors", core::any::type_name::<shared::surface::TriangleColors>),
];

const fn scene_binding(binding: u32, name: &'static str, element: fn() -> &'static str) -> Binding {
    Binding { set: SCENE_SET, binding, name, access: Access::Read, element }
}

/// Every buffer of an iteration as slices, by the names the stages bind them by: what a backend
/// hands a stage's `Io::from_bound`, which takes the ones the stage declares. `I` is the
/// splat's image (f32 bits on the device, f64 sums on the CPU backend).
pub struct Bound<'a, R, I: ?Sized> {
    #[allow(missing_docs)] // the dispatch's parameters
    pub params: &'a RenderParams,
    /// Chain samples, SoA (`p + i·N`).
    pub chain_u: &'a mut [f32],
    #[allow(missing_docs)] // the chains' states
    pub chains: &'a mut [ChainState],
    /// Candidate samples, SoA (`k + i·C`).
    pub cand_u: &'a mut [f32],
    /// Candidate path depths.
    pub cand_depth: &'a mut [u32],
    /// Subpath vertices, SoA (`k + slot·C`).
    pub vertices: &'a mut [PathVertex],
    /// One a candidate.
    pub paths: &'a mut [PathInfo],
    /// Packed contributions (`shared::layout`), one a candidate.
    pub contributions: &'a mut [Vec4],
    /// Splat records, one per distinct state of each chain.
    pub splats: &'a mut [Vec4],
    /// Ĩ per pixel, the pixel importance.
    pub importance: &'a [f32],
    /// The image the splats add to.
    pub image: &'a mut I,
    #[allow(missing_docs)] // the scene the stages trace
    pub scene: Scene<'a, R>,
}

/// A slice, shared or not, as a shared one (what a stage that only reads a buffer takes of it).
pub trait IntoRead<'a, T> {
    #[allow(missing_docs)] // the conversion
    fn into_read(self) -> &'a [T];
}

impl<'a, T> IntoRead<'a, T> for &'a [T] {
    fn into_read(self) -> &'a [T] {
        self
    }
}

impl<'a, T> IntoRead<'a, T> for &'a mut [T] {
    fn into_read(self) -> &'a [T] {
        self
    }
}

/// The `Io` field type of a binding of `kind` over `T`.
#[doc(hidden)]
#[macro_export]
macro_rules! stage_field {
    ($lt:lifetime, uniform, $ty:ty) => { &$lt $ty };
    ($lt:lifetime, read, $ty:ty) => { &$lt [$ty] };
    ($lt:lifetime, write, $ty:ty) => { &$lt mut [$ty] };
    ($lt:lifetime, sink, $ty:ty) => { &$lt mut $ty };
}

/// The entry point's parameter type of a binding of `kind` over `T` (a sink is the device's
/// image, f32 values as bits).
#[doc(hidden)]
#[macro_export]
macro_rules! stage_param {
    (uniform, $ty:ty) => {
        &[$ty]
    };
    (read, $ty:ty) => {
        &[$ty]
    };
    (write, $ty:ty) => {
        &mut [$ty]
    };
    (sink, $ty:ty) => {
        &mut [u32]
    };
}

/// The `Io` field's value from the entry point's parameter `$name`.
#[doc(hidden)]
#[macro_export]
macro_rules! stage_unpack {
    (uniform, $name:ident) => {
        &$name[0]
    };
    ($kind:ident, $name:ident) => {
        $name
    };
}

/// The `Io` field's value from the [`Bound`] field `$value`.
#[doc(hidden)]
#[macro_export]
macro_rules! stage_take {
    (read, $value:expr) => {
        $crate::stage::IntoRead::into_read($value)
    };
    ($kind:ident, $value:expr) => {
        $value
    };
}

/// A reborrow of the `Io` field `$name` for one invocation.
#[doc(hidden)]
#[macro_export]
macro_rules! stage_reborrow {
    (write, $name:ident) => {
        &mut *$name
    };
    (sink, $name:ident) => {
        &mut *$name
    };
    ($kind:ident, $name:ident) => {
        $name
    };
}

/// The [`Access`] of a binding of `kind`.
#[doc(hidden)]
#[macro_export]
macro_rules! stage_access {
    (uniform) => {
        $crate::stage::Access::Uniform
    };
    (read) => {
        $crate::stage::Access::Read
    };
    (write) => {
        $crate::stage::Access::Write
    };
    (sink) => {
        $crate::stage::Access::Write
    };
}

/// The element type name of a binding of `kind` over `T` on the device (a sink's is the
/// image's f32, which the kernel adds to as bits).
#[doc(hidden)]
#[macro_export]
macro_rules! stage_element {
    (sink, $ty:ty) => {
        core::any::type_name::<f32>
    };
    ($kind:ident, $ty:ty) => {
        core::any::type_name::<$ty>
    };
}

/// Declares a stage: its `Io` struct, its numbered bindings, its entry point with its
/// workgroup size, and its body `fn(invocation: usize, io: Io)`. See the module doc for what it
/// generates.
///
/// - `pub struct NameIo<'a>` binds no scene; `pub struct NameIo<'a> over scene R` traces the
///   scene over the ray caster `R` (its field `scene`, the scene's bindings in set 1);
///   `pub struct NameIo<'a> over image I` adds to the image `I: SplatSink` (a `sink` binding).
/// - Each binding is `N name: kind T`: `uniform` (one `T`, bound as `&[T]`), `read` or `write`
///   (slices of `T`), or `sink` (`&mut I`; on the device `&mut [u32]`, f32 values as bits).
/// - `entry "name_cs" (threads N) => body;` names the entry point (the module's `entry`) and
///   the body; `bound;` after it
///   also generates `from_bound` (for the render's stages, whose buffers are all in [`Bound`]).
#[macro_export]
macro_rules! stage {
    (
        $(#[$meta:meta])*
        pub struct $io:ident<$lt:lifetime> over scene $r:ident {
            $( $(#[$fmeta:meta])* $b:literal $name:ident : $kind:ident $ty:ty ),* $(,)?
        }
        entry $entry:literal (threads $threads:tt) => $body:path;
        $($from:ident;)?
    ) => {
        $(#[$meta])*
        pub struct $io<$lt, $r: shared::ray_caster::RayCaster> {
            $( #[doc = concat!("Binding ", stringify!($b), " (", stringify!($kind), ").")] $(#[$fmeta])* pub $name: $crate::stage_field!($lt, $kind, $ty), )*
            /// The scene over the ray caster.
            pub scene: shared::scene::Scene<$lt, $r>,
        }
        $crate::stage!(@consts $entry, true, $( $b $name $kind $ty ),*);
        $crate::stage!(@entry $io, $entry, $threads, $body, [$( $b $name $kind $ty ),*], [
            #[spirv(storage_buffer, descriptor_set = 1, binding = 0)] nodes: &[shared::cwbvh::WideNode],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 1)] triangles: &[shared::triangle::Triangle],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 2)] materials: &[shared::bsdf::Material],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 3)] lights: &[shared::light::LightEntry],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 4)] punctual: &[shared::punctual::PunctualLight],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 5)] environment: &[shared::environment::Environment],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 6)] environment_map: &[f32],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 7)] material_textures: &[shared::surface::MaterialTextures],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 8)] textures: &[shared::texture::Texture],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 9)] texels: &[u32],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 10)] texcoords: &[shared::surface::TriangleTexcoords],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 11)] normals: &[shared::normals::TriangleNormals],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 12)] tangents: &[shared::normal_map::TriangleTangents],
            #[spirv(storage_buffer, descriptor_set = 1, binding = 13)] colors: &[shared::surface::TriangleColors],
        ], [
            scene: shared::scene::Scene {
                caster: shared::cwbvh::WideBvh {
                    nodes,
                    triangles,
                    cutouts: shared::cutout::Cutouts {
                        triangles,
                        materials,
                        material_textures,
                        texcoords,
                        textures,
                        texels,
                    },
                },
                triangles,
                materials,
                lights,
                punctual,
                environment: &environment[0],
                environment_map,
                material_textures,
                textures,
                texels,
                texcoords,
                normals,
                tangents,
                colors,
            },
        ]);
        impl<$lt, $r: shared::ray_caster::RayCaster + Copy> $io<$lt, $r> {
            $crate::stage!(@run $io, $body, [$( $name $kind ),*], [scene]);
            $crate::stage!(@from_bound $($from)? [$lt, [BoundI: ?Sized], [$lt, $r, BoundI]], [$( $name $kind ),*], [scene]);
        }
    };
    (
        $(#[$meta:meta])*
        pub struct $io:ident<$lt:lifetime> over image $i:ident {
            $( $(#[$fmeta:meta])* $b:literal $name:ident : $kind:ident $ty:ty ),* $(,)?
        }
        entry $entry:literal (threads $threads:tt) => $body:path;
        $($from:ident;)?
    ) => {
        $(#[$meta])*
        pub struct $io<$lt, $i: $crate::splat::SplatSink + ?Sized> {
            $( #[doc = concat!("Binding ", stringify!($b), " (", stringify!($kind), ").")] $(#[$fmeta])* pub $name: $crate::stage_field!($lt, $kind, $ty), )*
        }
        $crate::stage!(@consts $entry, false, $( $b $name $kind $ty ),*);
        $crate::stage!(@entry $io, $entry, $threads, $body, [$( $b $name $kind $ty ),*], [], []);
        impl<$lt, $i: $crate::splat::SplatSink + ?Sized> $io<$lt, $i> {
            $crate::stage!(@run $io, $body, [$( $name $kind ),*], []);
            $crate::stage!(@from_bound $($from)? [$lt, [BoundR], [$lt, BoundR, $i]], [$( $name $kind ),*], []);
        }
    };
    (
        $(#[$meta:meta])*
        pub struct $io:ident<$lt:lifetime> {
            $( $(#[$fmeta:meta])* $b:literal $name:ident : $kind:ident $ty:ty ),* $(,)?
        }
        entry $entry:literal (threads $threads:tt) => $body:path;
        $($from:ident;)?
    ) => {
        $(#[$meta])*
        pub struct $io<$lt> {
            $( #[doc = concat!("Binding ", stringify!($b), " (", stringify!($kind), ").")] $(#[$fmeta])* pub $name: $crate::stage_field!($lt, $kind, $ty), )*
        }
        $crate::stage!(@consts $entry, false, $( $b $name $kind $ty ),*);
        $crate::stage!(@entry $io, $entry, $threads, $body, [$( $b $name $kind $ty ),*], [], []);
        impl<$lt> $io<$lt> {
            $crate::stage!(@run $io, $body, [$( $name $kind ),*], []);
            $crate::stage!(@from_bound $($from)? [$lt, [BoundR, BoundI: ?Sized], [$lt, BoundR, BoundI]], [$( $name $kind ),*], []);
        }
    };

    (@consts $entry:literal, $scene:expr, $( $b:literal $name:ident $kind:ident $ty:ty ),*) => {
        /// The entry point's name in the kernels module.
        pub const ENTRY_POINT: &str = $entry;

        /// The stage's own bindings (set 0), in binding order.
        pub const BINDINGS: &[$crate::stage::Binding] = &[
            $( $crate::stage::Binding {
                set: 0,
                binding: $b,
                name: stringify!($name),
                access: $crate::stage_access!($kind),
                element: $crate::stage_element!($kind, $ty),
            }, )*
        ];

        /// Whether the stage binds the scene too (`stage::SCENE_BINDINGS`, set 1).
        pub const BINDS_SCENE: bool = $scene;
    };

    (@entry $io:ident, $entry:literal, $threads:tt, $body:path,
        [$( $b:literal $name:ident $kind:ident $ty:ty ),*], [$($scene_params:tt)*], [$($scene_value:tt)*]) => {
        /// Entry point: one invocation per item of the stage, its bindings unpacked into the
        /// stage's `Io`.
        #[allow(clippy::too_many_arguments)]
        #[spirv_std::spirv(compute(threads($threads), entry_point_name = $entry))]
        pub fn entry(
            #[spirv(global_invocation_id)] id: spirv_std::glam::UVec3,
            $( #[spirv(storage_buffer, descriptor_set = 0, binding = $b)] $name: $crate::stage_param!($kind, $ty), )*
            $($scene_params)*
        ) {
            let io = $io { $( $name: $crate::stage_unpack!($kind, $name), )* $($scene_value)* };
            $body(id.x as usize, io);
        }
    };

    (@run $io:ident, $body:path, [$( $name:ident $kind:ident ),*], [$($scene:ident)?]) => {
        /// The body over invocations `0..invocations`, in order (the CPU backend).
        pub fn run(self, invocations: usize) {
            let $io { $( $name, )* $( $scene, )? } = self;
            for i in 0..invocations {
                $body(i, $io { $( $name: $crate::stage_reborrow!($kind, $name), )* $( $scene, )? });
            }
        }
    };

    (@from_bound [$($rest:tt)*], [$( $name:ident $kind:ident ),*], [$($scene:ident)?]) => {};
    (@from_bound bound [$lt:lifetime, [$($gen:tt)*], [$($args:tt)*]], [$( $name:ident $kind:ident ),*], [$($scene:ident)?]) => {
        /// The stage's bindings taken by name from a backend's buffers (the rest are dropped).
        pub fn from_bound<$($gen)*>(b: $crate::stage::Bound<$($args)*>) -> Self {
            Self { $( $name: $crate::stage_take!($kind, b.$name), )* $( $scene: b.$scene, )? }
        }
    };
}

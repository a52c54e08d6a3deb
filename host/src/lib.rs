//! The smlt renderer: scenes, device set-up, the passes (buffers and dispatch of each kernel, on
//! the GPU or on CPU threads), the render loop, part files and ground truth. The `smlt` command
//! (`cli/`) and the measurement tools (`smlt-bench`, `bench/`) are built on it.
#![deny(missing_docs)]

pub mod caster;
pub mod gpu;
pub mod hash;
pub mod output;
pub mod part;
pub mod passes;
pub mod reference;
pub mod render;
pub mod scene;
pub mod scenes;
pub mod selftest;
pub mod timing;

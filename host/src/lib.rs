//! The smlt host: device set-up, the passes (buffers and dispatch of each kernel, on the GPU or
//! on CPU threads), and the commands of the `smlt` binary.
#![deny(missing_docs)]

pub mod bench;
pub mod caster;
pub mod cmd;
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

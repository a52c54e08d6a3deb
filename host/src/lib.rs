//! The smlt host: device set-up, the passes (buffers and dispatch of each kernel, on the GPU or
//! on CPU threads), and the commands of the `smlt` binary.
#![deny(missing_docs)]

pub mod gpu;
pub mod passes;
pub mod selftest;

//! One file a pass: the buffers and the dispatch of one kernel, and the same kernel body run
//! on CPU threads.

pub mod selftest;

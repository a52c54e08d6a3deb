//! The `smlt` command line, one file a subcommand — its arguments and what it runs — as
//! pbrt-v4's `cmd/`; [`args`] holds what several share (the device, the scene, the parsers).

pub mod args;
pub mod bench;
pub mod devices;
pub mod merge;
pub mod plot;
pub mod reference;
pub mod render;
pub mod scene;
pub mod selftest;

use clap::{Parser, Subcommand};

/// The command line.
#[derive(Parser)]
#[command(name = "smlt", version, about = "Coherent Metropolis light transport with speculative mutations")]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands (their doc comments are their help texts).
#[derive(Subcommand)]
pub enum Command {
    /// Renders a glTF scene with Multiplexed MLT on the GPU (or the CPU).
    Render(render::Args),
    /// Merges the part files of a render split with --shard K/N into its image.
    Merge(merge::Args),
    /// Lists the Vulkan adapters (index, name, type, backend, driver) and the CPU backend.
    Devices,
    /// Renders a scene's ground truth with an independent path tracer (next-event estimation and
    /// MIS), cached on disk with its settings.
    Reference(reference::Args),
    /// Equal-time comparison of the methods against reference images: CSV, tables, heat maps.
    Bench(bench::Args),
    /// Draws the bench's plots (speedup.png, error_<scene>_v<view>.png) and tables.md from a
    /// results.csv (also one that holds peers' rows).
    Plot(plot::Args),
    /// Writes one of the generated scenes as glTF.
    Scene(scene::Args),
    /// Opens the Vulkan adapter, prints its name, and checks that the device computes the
    /// speculative-tree, reject-chain and mutation math exactly as the CPU does.
    Selftest(selftest::Args),
}

impl Command {
    /// Runs the subcommand.
    pub fn run(self) -> anyhow::Result<()> {
        match self {
            Command::Render(a) => render::run(a),
            Command::Merge(a) => merge::run(a),
            Command::Devices => devices::run(),
            Command::Reference(a) => reference::run(a),
            Command::Bench(a) => bench::run(a),
            Command::Plot(a) => plot::run(a),
            Command::Scene(a) => scene::run(a),
            Command::Selftest(a) => selftest::run(a),
        }
    }
}

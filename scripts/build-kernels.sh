#!/usr/bin/env bash
# Rebuilds the kernels module (kernels/spirv/kernels.spv and inputs.hash) from the kernels' and
# shared's sources with rust-gpu, after a kernel or shared change; commit both files with the
# change. `--check` rebuilds and fails if the committed module differs (what CI runs).
# The first run builds rust-gpu's backend (about 10-25 minutes on 2 cores; later runs seconds).
set -euo pipefail
cd "$(dirname "$0")/../builder"
# The builder's toolchain file names the nightly with rustc-dev and llvm-tools; rustup >= 1.28
# installs what it names (nothing installs implicitly on our machines: RUSTUP_AUTO_INSTALL=0).
rustup toolchain install >/dev/null
export CARGO_TARGET_DIR="${SMLT_BUILDER_TARGET_DIR:-${CARGO_TARGET_DIR:-$PWD/target}}"
# Cargo keys the fingerprints of path packages by their path inside the workspace, not by the
# checkout, so a target directory shared by two checkouts can take one checkout's builder or
# kernels for the other's (seen here: a clone's builder hashed the wrong sources). Forget this
# project's own crates there; rust-gpu's backend and the other dependencies stay built.
rm -rf "$CARGO_TARGET_DIR"/release/build/smlt-kernel-builder/*/fingerprint \
    "$CARGO_TARGET_DIR"/spirv-builder/*/release/build/kernels/*/fingerprint \
    "$CARGO_TARGET_DIR"/spirv-builder/*/release/build/shared/*/fingerprint 2>/dev/null || true
cargo run --release --quiet -- "$@"

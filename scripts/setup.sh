#!/usr/bin/env bash
# Installs what smlt needs, idempotently, and says exactly what to run where it cannot:
#  - the nightly pinned in rust-toolchain.toml (nothing installs it implicitly here); the
#    kernels' SPIR-V module is committed, so a renderer needs no more of it — rust-gpu's
#    backend and its rustc-dev and llvm-tools are installed by scripts/build-kernels.sh, for
#    kernel developers only;
#  - when no Vulkan driver is installed, Debian's Vulkan loader and lavapipe, Mesa's CPU
#    Vulkan driver (packages libvulkan1 and mesa-vulkan-drivers);
#  - when no C++ compiler is installed, Debian's g++: the build compiles meshoptimizer's decoder
#    (EXT_meshopt_compression) from its C++ source;
#  - when it is missing, Intel Embree (libembree3-3): the CPU backend's fastest ray caster,
#    loaded at run time. smlt runs without it (rays through obvhs's traversal, 1.5-2.7x
#    slower), so where it cannot be installed this only prints a note.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v rustup >/dev/null 2>&1; then
    echo "error: rustup not found; install it (https://rustup.rs), then rerun $0" >&2
    exit 1
fi
# With no argument, rustup (>= 1.28) installs the toolchain and components that
# rust-toolchain.toml names; it does nothing when they are present.
rustup toolchain install >/dev/null

# grep reads ldconfig's whole list (not -q): with pipefail, an early exit of grep would make
# ldconfig die of SIGPIPE now and then, and the library read as missing.
has_vulkan_loader() { ldconfig -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null; }
has_vulkan_driver() {
    [ -n "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && return 0
    local d
    for d in /usr/share/vulkan/icd.d /etc/vulkan/icd.d /usr/local/share/vulkan/icd.d; do
        compgen -G "$d/*.json" >/dev/null && return 0
    done
    return 1
}

has_embree() { ldconfig -p 2>/dev/null | grep 'libembree3\.so\.3' >/dev/null; }
can_apt() { [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; }

vulkan_packages=""
if ! has_vulkan_loader || ! has_vulkan_driver; then
    vulkan_packages="libvulkan1 mesa-vulkan-drivers"
fi
build_packages=""
command -v c++ >/dev/null 2>&1 || build_packages="g++"
required="$vulkan_packages${build_packages:+ $build_packages}"
required="${required# }"
embree_packages=""
has_embree || embree_packages="libembree3-3"
if [ -n "$required$embree_packages" ] && can_apt; then
    echo "setup: installing $required${embree_packages:+ $embree_packages}" >&2
    apt-get update -qq
    if [ -n "$required" ]; then
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $required >/dev/null
    fi
    if [ -n "$embree_packages" ]; then
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $embree_packages >/dev/null ||
            echo "note: could not install $embree_packages; the CPU backend casts rays without Embree (slower)" >&2
    fi
elif [ -n "$required" ]; then
    echo "error: no Vulkan driver or no C++ compiler found, and cannot install here (needs root and apt-get);" >&2
    echo "       run: sudo apt-get install $required   (or install your GPU's Vulkan driver)" >&2
    exit 1
elif [ -n "$embree_packages" ]; then
    echo "note: Embree not found; the CPU backend casts rays without it (slower): sudo apt-get install $embree_packages" >&2
fi

#!/usr/bin/env bash
# The project's one test command (see README): builds, then runs every test of the workspace.
#
# The viewport's and editor's image tests render offscreen on a software Vulkan driver
# (Mesa's lavapipe). When none is installed, this installs it (Debian: mesa-vulkan-drivers),
# as root or through sudo. Tests run under cargo-nextest (settings in .config/nextest.toml:
# every test in its own process, the long property tests started first); without it, under
# `cargo test`. Extra arguments go to the runner (`--profile quick` skips the slow group).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
    echo "scripts/test.sh: installing the software Vulkan driver (mesa-vulkan-drivers)" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mesa-vulkan-drivers >/dev/null
fi
# The meshopt crate (EXT_meshopt_compression) builds meshoptimizer's C++ sources and the ufbx
# crate (FBX) the ufbx C library: a C and C++ compiler must exist. Debian images without one
# get g++ (which brings gcc).
if ! command -v c++ >/dev/null 2>&1; then
    echo "scripts/test.sh: installing a C and C++ compiler (g++) for the meshopt and ufbx crates" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq g++ >/dev/null
fi
# lavapipe complains without a runtime dir; give it one.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
jobs="${CARGO_BUILD_JOBS:-$(nproc)}"
# Property tests draw from a fixed seed here so that a run is reproducible and CI never fails
# on a case no one has seen; set PROPTEST_RNG_SEED to explore others, or run scripts/fuzz.sh.
export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261123}"

if cargo nextest --version >/dev/null 2>&1; then
    cargo nextest run --workspace --locked --build-jobs "$jobs" "$@"
else
    echo "scripts/test.sh: cargo-nextest not found, using cargo test (cargo install cargo-nextest for faster runs)" >&2
    cargo test --workspace --locked -j"$jobs" "$@"
fi

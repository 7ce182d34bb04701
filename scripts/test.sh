#!/usr/bin/env bash
# The project's one test command (see README): runs every test of the workspace.
# Later issues add system packages here (e.g. a software Vulkan driver for offscreen images).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --locked -j"${CARGO_BUILD_JOBS:-2}" "$@"

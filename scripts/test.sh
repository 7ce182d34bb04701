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
# The suite builds from scratch without incremental compilation's bookkeeping: a cold run's
# build takes 9m58s instead of 11m12s on two cores. Cargo keeps the two kinds of build apart,
# so after plain `cargo` builds (incremental) the first run here compiles the workspace's crates
# again; CARGO_INCREMENTAL=1 bash scripts/test.sh shares their build instead.
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
# Property tests draw from a fixed seed here so that a run is reproducible and CI never fails
# on a case no one has seen; set PROPTEST_RNG_SEED to explore others, or run scripts/fuzz.sh.
export PROPTEST_RNG_SEED="${PROPTEST_RNG_SEED:-20261123}"

# The Python module (crates/python) is built as an extension module: cargo unifies dependency
# features over the packages of one invocation, so every build below names the same packages
# and features, and the module's build reuses the tests' starcages-core and starcages-io.
python_module=(--features starcages-python/extension-module)

# Everything is built first: the tests, the CLI and the Python package's extension module.
# The Python package (crates/python): its extension module, built by cargo in the same
# dependency graph as the Rust tests (only PyO3, numpy and the crate itself compile here; a
# `maturin build` resolves the crate alone and compiles starcages-core and -io again, 2 of 10
# minutes of a cold run), is put on PYTHONPATH as `starcages` and tested with pytest against
# starcages-cli in a virtual environment (target/python-venv, which gets numpy and pytest from
# the package registry when it lacks them). CI builds the wheel itself with maturin and runs the
# same tests on it (.ci/run). Debian images without Python 3.11+ or its venv module get them.
cargo build --workspace --lib --tests --locked -j"$jobs" "${python_module[@]}"
module_dir=target/python-module
rm -rf "$module_dir" && mkdir -p "$module_dir"
cp target/debug/libstarcages.so "$module_dir/starcages.abi3.so"
cp crates/python/starcages.pyi "$module_dir/"
export PYTHONPATH="$PWD/$module_dir${PYTHONPATH:+:$PYTHONPATH}"
python=$(command -v python3 || true)
if [ -z "$python" ] || ! "$python" -c 'import sys, venv, ensurepip; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; then
    echo "scripts/test.sh: installing Python 3 with venv for the Python package's tests" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3 python3-venv >/dev/null
    python=$(command -v python3)
fi
venv=target/python-venv
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
if ! "$venv/bin/python" -c 'import numpy, pytest' 2>/dev/null; then
    "$venv/bin/python" -m pip install -q --disable-pip-version-check numpy pytest
fi
# The CLI binary the build above made for the tests (a `cargo build -p starcages-cli` would resolve
# the package's features alone and compile much of the workspace again: 1m43s cold).
test -x target/debug/starcages-cli
# PYTHONPATH comes before site-packages: a wheel installed there earlier is not what is tested.
"$venv/bin/python" -c "import starcages, sys; sys.exit(not starcages.__file__.startswith('$PWD/$module_dir/'))"

# The Blender extension (blender/starcages_extension): its tests run headless through the bpy
# package (Blender as a Python module, about 370 MB; it needs the Python version Blender
# ships, 3.11 for Blender 5) in a throw-away virtual environment (target/bpy-venv), when it can
# be installed; otherwise they are skipped with a note.
bpy_venv=target/bpy-venv
if ! "$bpy_venv/bin/python" -c 'import bpy' 2>/dev/null; then
    rm -rf "$bpy_venv"
    if ! { "$python" -m venv "$bpy_venv" &&
        timeout 600 "$bpy_venv/bin/python" -m pip install -q --no-cache-dir --disable-pip-version-check bpy; }; then
        # A half-installed venv (a full disk, a timeout) would take the space the rest needs.
        rm -rf "$bpy_venv"
        echo "scripts/test.sh: the bpy package could not be installed for $("$python" --version): the Blender extension's tests are skipped" >&2
    fi
fi
# The two Python suites (mostly one thread each) run in the background beside the Rust tests,
# at the same priority: at the lowest, the Blender run was starved until the Rust tests ended
# and then ran alone on one core (warm run 138 s; 117 s so). Their output follows the Rust
# tests'. A failure of the Rust tests ends the script and the Python runs with it.
python_out=$(mktemp -d)
STARCAGES_CLI="$PWD/target/debug/starcages-cli" "$venv/bin/python" -m pytest -q \
    -p no:cacheprovider crates/python/tests >"$python_out/pytest.log" 2>&1 &
pytest_pid=$!
blender_pid=""
if "$bpy_venv/bin/python" -c 'import bpy' 2>/dev/null; then
    "$bpy_venv/bin/python" scripts/blender_extension_test.py \
        "$PWD/target/debug/starcages-cli" "$python_out" >"$python_out/blender.log" 2>&1 &
    blender_pid=$!
fi
trap 'kill $pytest_pid $blender_pid 2>/dev/null || true; rm -rf "$python_out"' EXIT

if cargo nextest --version >/dev/null 2>&1; then
    cargo nextest run --workspace --locked --build-jobs "$jobs" "${python_module[@]}" "$@"
else
    echo "scripts/test.sh: cargo-nextest not found, using cargo test (cargo install cargo-nextest for faster runs)" >&2
    cargo test --workspace --locked -j"$jobs" "${python_module[@]}" "$@"
fi

if ! wait "$pytest_pid"; then
    cat "$python_out/pytest.log" >&2
    exit 1
fi
tail -n 1 "$python_out/pytest.log"
if [ -n "$blender_pid" ]; then
    if ! wait "$blender_pid"; then
        grep -v '^EGL' "$python_out/blender.log" >&2
        exit 1
    fi
    grep -E '^(undo|bent|Blender|reopened|control drag|import|cage|keyed|bake|blender extension)' "$python_out/blender.log"
fi

#!/usr/bin/env bash
# Fuzzes every reader (scene JSON with its animation, mesh OBJ, FBX, PLY, STL, OFF, glTF/GLB with
# skins and meshopt, cage OBJ, points, point caches, binding cache), every writer against those
# readers (point caches, animated glTF, OBJ and GLB meshes: what we write reads back) and the
# auto rig's settings for a while: the proptest harnesses of
# crates/io/tests/integration/fuzz_readers.rs, mesh_formats.rs, fbx.rs and written_files.rs, and
# the auto rig on random unions of capsules under random detail, mirror and internal-cage settings
# (crates/core/tests/integration/autorig.rs: valid, and symmetric when asked), run again and again with fresh random seeds,
# until the time is up or something panics, hangs or fails.
#
#   bash scripts/fuzz.sh [SECONDS]      (default 600: ten minutes)
#
# Prints the number of inputs tried. Each run has a time limit, so a hang fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
cases=2000
# Random shapes the auto rig is tried on per run (each a fraction of a second).
rig_cases=40
# Inputs per case: scene (damaged + raw), OBJ (2 files × 4 readers), glTF (mutated + GLB),
# binding cache (damaged + crafted), point caches (2 formats × 2 files × 2 reads), PLY, STL and
# OFF (6 damaged files), FBX (a binary and an ASCII file, damaged); written files: an animation
# baked through 3 writers and read back, a mesh through 2.
per_case=$((2 + 8 + 2 + 2 + 8 + 6 + 2 + 3 + 2))
cargo test -p starcages-io -p starcages-core --test integration --no-run --quiet 2>/dev/null
start=$(date +%s)
runs=0
while [ $(( $(date +%s) - start )) -lt "$seconds" ]; do
    if ! STARCAGES_FUZZ_CASES=$cases timeout 600 \
        cargo test -p starcages-io --test integration --quiet -- fuzz_readers mesh_formats::damaged fbx::damaged written_files >/tmp/starcages-fuzz.log 2>&1; then
        cat /tmp/starcages-fuzz.log
        echo "fuzz: FAILED after $runs runs ($((runs * cases * per_case)) inputs); see above" >&2
        exit 1
    fi
    if ! STARCAGES_AUTORIG_CASES=$rig_cases timeout 600 \
        cargo test -p starcages-core --test integration --quiet -- random_shapes >/tmp/starcages-fuzz.log 2>&1; then
        cat /tmp/starcages-fuzz.log
        echo "fuzz: the auto rig FAILED after $runs runs; see above" >&2
        exit 1
    fi
    runs=$((runs + 1))
done
echo "fuzz: $((runs * cases * per_case)) inputs and $((runs * rig_cases)) auto rigs in $runs runs over $(( $(date +%s) - start )) s: no panic, hang or failure"

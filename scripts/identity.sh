#!/usr/bin/env bash
# Fingerprints of what the CLI writes: every demo scene, each deformed, the critter's animation
# baked to PC2, MDD and GLB, its cages over the frames, an auto rig of the creature's mesh (with
# and without controls) and that rig posed through its controls. Run it before and after a
# refactor that must not change behaviour and compare the two lists:
#   bash scripts/identity.sh > before.txt; …; bash scripts/identity.sh > after.txt
#   diff before.txt after.txt
# Files are written under one fixed folder (scene files name their mesh by path, so the folder
# must not change between runs). Needs no ../shared.
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-target/release/starcages-cli}"
work=/tmp/starcages-identity
rm -rf "$work"
mkdir -p "$work"
run() { "$cli" "$@" >/dev/null 2>&1 || { echo "identity.sh: failed: $*" >&2; exit 1; }; }

run demo all --out "$work"
for scene in "$work"/*.json; do
    name="$(basename "$scene" .json)"
    run deform "$scene" --out "$work/$name.deformed.obj"
done
critter="$work/critter.json"
for format in pc2 mdd glb; do
    run bake "$critter" --out "$work/critter.$format"
done
run cages "$critter" --out "$work/critter.cages.pc2"
run cages "$critter" --out "$work/critter.cages.obj"
run deform "$critter" --frame 12 --apply "ear_left: rotate 1 0 0 20" --out "$work/critter.f12.obj"
run deform "$critter" --frame 12 --apply "head: rotate 0 0 1 10" --out "$work/critter.f12head.obj"
run deform "$critter" --frame 6.5 --out "$work/critter.f6.obj"
run autorig "$work/creature.deformed.obj" --out "$work/auto.json"
run autorig "$work/creature.deformed.obj" --no-controls --detail 2 --out "$work/auto_bare.json"
run deform "$work/auto.json" --apply "leg.front.R.1: rotate 0 1 0 35" \
    --apply "leg.front.R.2: rotate 0 1 0 -60" --out "$work/auto.posed.obj"
run bake "$work/creature.json" --out "$work/creature.pc2"
cd "$work"
sha256sum -- * | sort -k2

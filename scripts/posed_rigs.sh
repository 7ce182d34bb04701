#!/usr/bin/env bash
# The README's pictures of posed auto rigs: a humanoid walking (the armadillo), a quadruped
# lifting a front leg (the horse), a humanoid with thick knees stepping and turning its head
# (the beast) and a creature (the creature demo's mesh), each made by `autorig` with its controls and posed by
# `render --apply` on them. Needs ../shared/meshes.
#   bash scripts/posed_rigs.sh [path/to/starcages-cli]
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-target/release/starcages-cli}"
meshes=../shared/meshes
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$cli" autorig "$meshes/armadillo.obj" --out "$work/armadillo.json" >/dev/null
"$cli" render "$work/armadillo.json" --no-cages --view side --size 480x480 \
    --apply "leg.L.1: rotate 1 0 0 30" --apply "leg.L.2: rotate 1 0 0 -50" \
    --apply "leg.R.1: rotate 1 0 0 -20" --apply "arm.L.1: rotate 0 1 0 45" \
    --apply "arm.R.1: rotate 0 -1 0 45" --apply "arm.R.2: rotate 1 0 0 40" \
    --apply "tail.1: rotate 0 0 1 20" --apply "head.1: rotate 0 0 1 -25" \
    --png docs/images/posed_armadillo.png >/dev/null
"$cli" autorig "$meshes/horse.obj" --out "$work/horse.json" >/dev/null
"$cli" render "$work/horse.json" --no-cages --view side --size 480x480 \
    --apply "leg.front.L.1: rotate 1 0 0 35" --apply "leg.front.L.3: rotate 1 0 0 -80" \
    --apply "neck.1: rotate 1 0 0 -30" --png docs/images/posed_horse.png >/dev/null
"$cli" autorig "$meshes/beast.obj" --out "$work/beast.json" >/dev/null
"$cli" render "$work/beast.json" --no-cages --view side --size 480x480 \
    --apply "leg.L.1: rotate 1 0 0 -35" --apply "leg.L.2: rotate 1 0 0 55" \
    --apply "leg.R.1: rotate 1 0 0 20" --apply "arm.L.1: rotate 1 0 0 25" \
    --apply "arm.R.1: rotate 1 0 0 -25" --apply "arm.R.3: rotate 1 0 0 -40" \
    --apply "head.1: rotate 0 0 1 -25" --apply "head.1: rotate 1 0 0 15" \
    --png docs/images/posed_beast.png >/dev/null
"$cli" demo creature --out "$work" >/dev/null
"$cli" deform "$work/creature.json" --out "$work/creature.obj" >/dev/null
"$cli" autorig "$work/creature.obj" --out "$work/creature_auto.json" >/dev/null
"$cli" render "$work/creature_auto.json" --no-cages --view front --size 480x480 \
    --apply "tail.1: rotate 0 1 0 -30" --apply "head.1: rotate 0 0 1 25" \
    --apply "leg.front.R.1: rotate 0 1 0 35" --apply "leg.front.R.2: rotate 0 1 0 -60" \
    --png docs/images/posed_creature.png >/dev/null
echo "wrote docs/images/posed_armadillo.png, posed_horse.png, posed_beast.png, posed_creature.png"

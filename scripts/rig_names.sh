#!/usr/bin/env bash
# The auto rig's regression check: each mesh at details 1-5, with and without `--mirror auto`,
# rigged by a given CLI; per rig one line of its controls as `name<parent`, and its leaf cages'
# count. Run it with the build before and after a change to the rig and compare the two
# folders (`--compare`): the rigs whose controls or cages changed are the ones to look at.
#   bash scripts/rig_names.sh CLI OUT_DIR [MESH.obj ...]     (default: ../shared/meshes' seven)
#   bash scripts/rig_names.sh --compare BEFORE_DIR AFTER_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--compare" ]]; then
    before="$2"
    after="$3"
    changed=0
    for file in "$before"/*.names; do
        name="$(basename "$file" .names)"
        if ! cmp -s "$file" "$after/$name.names" || ! cmp -s "$before/$name.cages" "$after/$name.cages"; then
            echo "changed: $name"
            echo "  before: $(cat "$file")"
            echo "  after:  $(cat "$after/$name.names" 2>/dev/null || echo missing)"
            changed=$((changed + 1))
        fi
    done
    echo "$changed of $(ls "$before"/*.names | wc -l) rigs changed"
    exit 0
fi
cli="$1"
out="$2"
shift 2
meshes=("$@")
if [[ ${#meshes[@]} -eq 0 ]]; then
    for m in armadillo beast horse spot stanford-bunny qmvc/Ogre qmvc/ManHead; do
        meshes+=("../shared/meshes/$m.obj")
    done
fi
mkdir -p "$out"
for mesh in "${meshes[@]}"; do
    stem="$(basename "$mesh" .obj)"
    for detail in 1 2 3 4 5; do
        for mirror in "" "--mirror auto"; do
            tag="${stem}_${detail}${mirror:+_m}"
            # shellcheck disable=SC2086 # $mirror is two words or none
            if ! "$cli" autorig "$mesh" --detail "$detail" $mirror --out "$out/$tag.json" \
                >"$out/$tag.log" 2>&1; then
                echo "failed" >"$out/$tag.names"
                : >"$out/$tag.cages"
                continue
            fi
            "$cli" info --json "$out/$tag.json" | python3 -c '
import json, sys
info = json.load(sys.stdin)
print(" ".join(c["name"] + "<" + str(c.get("parent")) for c in info.get("controls", [])))
' >"$out/$tag.names"
            python3 -c '
import json, sys
scene = json.load(open(sys.argv[1]))
print(len(scene["cages"]), len(scene["cage_vertices"]))
' "$out/$tag.json" >"$out/$tag.cages"
        done
    done
done
echo "$(ls "$out"/*.names | wc -l) rigs in $out"

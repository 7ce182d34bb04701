#!/usr/bin/env python3
"""Is an auto rig its own mirror image? (`starcages-cli autorig MESH --mirror AXIS`)

Usage: symmetry_check.py SCENE.json AXIS

AXIS is x, y or z of the scene file's cage coordinates, which are StarCages' Z-up frame (a
Y-up mesh file's z is the scene's y). The plane is the centre of the leaf cages' extent along
AXIS. Prints how many leaf cage vertices have no mirror image among the leaf vertices (to a
millionth of the diagonal), the largest distance between an image and the vertex found for it
(relative to the diagonal), and the leaf cages whose mirrored faces are no leaf cage's faces.
Exit status 1 when the rig is not symmetric.
"""

import json
import sys


def main() -> int:
    if len(sys.argv) != 3 or sys.argv[2] not in ("x", "y", "z"):
        print(__doc__, file=sys.stderr)
        return 2
    path, axis = sys.argv[1], "xyz".index(sys.argv[2])
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    vertices = scene["cage_vertices"]
    leaf_vertices = {v for leaf in scene["cages"] for face in leaf["faces"] for v in face}
    points = [vertices[i] for i in leaf_vertices]
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    centre = (lo[axis] + hi[axis]) / 2
    diagonal = sum((h - l) ** 2 for l, h in zip(lo, hi)) ** 0.5

    def key(p):
        return tuple(round(x / diagonal * 1e6) for x in p)

    index = {}
    for i in leaf_vertices:
        index.setdefault(key(vertices[i]), i)
    image, missing, worst = {}, 0, 0.0
    for i in leaf_vertices:
        q = list(vertices[i])
        q[axis] = 2 * centre - q[axis]
        j = index.get(key(q))
        if j is None:
            missing += 1
            continue
        image[i] = j
        worst = max(worst, max(abs(a - b) for a, b in zip(vertices[j], q)) / diagonal)
    face_sets = {frozenset(frozenset(f) for f in leaf["faces"]) for leaf in scene["cages"]}
    twinless = [
        leaf["name"]
        for leaf in scene["cages"]
        if frozenset(frozenset(image.get(v, -1) for v in f) for f in leaf["faces"])
        not in face_sets
    ]
    print(
        f"{path}: {len(leaf_vertices)} leaf vertices, {missing} without an image, worst image "
        f"error {worst:.1e} of the diagonal, {len(twinless)} leaf cages without a mirror twin "
        f"{twinless[:6]}"
    )
    return 0 if missing == 0 and not twinless else 1


if __name__ == "__main__":
    sys.exit(main())

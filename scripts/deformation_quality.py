#!/usr/bin/env python3
"""Fold-overs and stretch of a deformed mesh against its rest pose.

Usage: scripts/deformation_quality.py REST.obj POSED.obj

Both OBJ files must list the same vertices and faces in the same order (as
`starcages-cli deform --out` writes them for one scene). Prints, as JSON:
- folds: interior edges whose two triangles turned against each other (the angle between
  their normals grew past 90 degrees while it was under 60 at rest): fold-overs and spikes;
- flipped: triangles whose normal turned more than 90 degrees away from the mean normal of
  their neighbours in the pose, while within 60 degrees of it at rest;
- edge ratio min / max: the extremes of posed over rest edge length;
- edges stretched over 2x or squashed under 0.5x.
Plain Python, no packages: a developer runs it on `deform` outputs of an auto rig and of a
hand-built rig posed alike (docs/autorig.md).
"""

import json
import math
import sys
from plain_obj import read_obj as read_polygons  # noqa: E402  (beside this script)


def read_obj(path):
    """Positions and triangles (polygons fanned) of an OBJ file."""
    positions, polygons = read_polygons(path)
    faces = [(f[0], f[k], f[k + 1]) for f in polygons for k in range(1, len(f) - 1)]
    return positions, faces


def normal(p, tri):
    a, b, c = (p[i] for i in tri)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = math.sqrt(sum(x * x for x in n))
    return [x / length for x in n] if length > 0 else [0.0, 0.0, 0.0]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rest, faces = read_obj(sys.argv[1])
    posed, posed_faces = read_obj(sys.argv[2])
    if len(rest) != len(posed) or faces != posed_faces:
        sys.exit("the two files do not list the same vertices and faces")
    n_rest = [normal(rest, t) for t in faces]
    n_posed = [normal(posed, t) for t in faces]
    edges = {}
    for f, (a, b, c) in enumerate(faces):
        for x, y in ((a, b), (b, c), (c, a)):
            edges.setdefault((min(x, y), max(x, y)), []).append(f)
    folds = 0
    neighbours = [[] for _ in faces]
    for pair in edges.values():
        if len(pair) == 2:
            f, g = pair
            neighbours[f].append(g)
            neighbours[g].append(f)
            if dot(n_rest[f], n_rest[g]) > 0.5 and dot(n_posed[f], n_posed[g]) < 0.0:
                folds += 1
    flipped = 0
    for f, near in enumerate(neighbours):
        if not near:
            continue
        mean_rest = [sum(n_rest[g][k] for g in near) for k in range(3)]
        mean_posed = [sum(n_posed[g][k] for g in near) for k in range(3)]
        r = math.sqrt(dot(mean_rest, mean_rest)) or 1.0
        q = math.sqrt(dot(mean_posed, mean_posed)) or 1.0
        if dot(n_rest[f], mean_rest) / r > 0.5 and dot(n_posed[f], mean_posed) / q < 0.0:
            flipped += 1
    ratios = []
    for a, b in edges:
        lr = math.dist(rest[a], rest[b])
        if lr > 0:
            ratios.append(math.dist(posed[a], posed[b]) / lr)
    print(json.dumps({
        "triangles": len(faces),
        "folds": folds,
        "flipped": flipped,
        "edge_ratio_min": round(min(ratios), 4),
        "edge_ratio_max": round(max(ratios), 4),
        "edges_stretched_over_2x": sum(r > 2.0 for r in ratios),
        "edges_squashed_under_half": sum(r < 0.5 for r in ratios),
    }))


if __name__ == "__main__":
    main()

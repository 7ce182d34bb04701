#!/usr/bin/env python3
"""Rest identity and rigid turns on real meshes, through the release CLI.

Usage: scripts/rest_identity.py MESH_FOLDER [STARCAGES_CLI]
       (e.g. scripts/rest_identity.py ../shared/meshes target/release/starcages-cli)

For every OBJ in the folder and a 3x3x3 and a 4x4x4 automatic grid (`autocage`): every leaf
cage MVC, HC and GC with the default (mean value) join cages, and every leaf MVC with the
automatic join policy (harmonic where concave) and with harmonic join cages everywhere. Each scene is deformed at rest (`deform`) and
with the whole rig turned by 30 degrees about a skew axis through the mesh's centre
(`--pose-file`; vertices no face uses are written unmoved and left out); prints, per case, the largest distance to the mesh (at rest) and to the mesh
turned alike, over the bounding-box diagonal, as one JSON line. Files are read and written in
the mesh file's axes (the OBJ's own). Plain Python, no packages; a developer's check, not a test.

2026-11-26, the five meshes of ../shared/meshes, 50 cases: at rest every case within 3.4e-8 of
the diagonal; turned, mean value and Green leaves (default joins) within 2.5e-7, harmonic
leaves within 1.2e-4 and harmonic joins (auto or everywhere) within 1.4e-3 (the grid's
linear-precision error, docs/math.md).
"""

import json
import math
import os
import subprocess
import sys
import tempfile


def read_vertices(path):
    with open(path, encoding="utf-8") as f:
        return [
            tuple(float(x) for x in line.split()[1:4]) for line in f if line.startswith("v ")
        ]


def used_vertices(path):
    """Indices of the vertices some face uses: `deform` writes the others as they are."""
    used = set()
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("f "):
                for corner in line.split()[1:]:
                    used.add(int(corner.split("/")[0]) - 1)
    return sorted(used)


def rotation(axis, degrees):
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    t = 1 - c
    return [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]


def turn(matrix, centre, p):
    d = [p[i] - centre[i] for i in range(3)]
    return tuple(centre[i] + sum(matrix[i][j] * d[j] for j in range(3)) for i in range(3))


def run(cli, *args):
    subprocess.run([cli, *args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    folder = sys.argv[1]
    cli = sys.argv[2] if len(sys.argv) > 2 else "target/release/starcages-cli"
    matrix = rotation((1.0, 2.0, 0.5), 30.0)
    with tempfile.TemporaryDirectory() as tmp:
        for name in sorted(os.listdir(folder)):
            if not name.endswith(".obj"):
                continue
            mesh_path = os.path.join(folder, name)
            source = read_vertices(mesh_path)
            used = used_vertices(mesh_path)
            lo = [min(p[i] for p in source) for i in range(3)]
            hi = [max(p[i] for p in source) for i in range(3)]
            diagonal = math.dist(lo, hi)
            centre = [(lo[i] + hi[i]) / 2 for i in range(3)]
            for grid in ("3", "4"):
                grid_scene = os.path.join(tmp, "grid.json")
                run(cli, "autocage", mesh_path, "--grid", grid, grid, grid, "--out", grid_scene)
                with open(grid_scene, encoding="utf-8") as f:
                    scene = json.load(f)
                for kind, joins in (("mvc", "mvc"), ("hc", "mvc"), ("gc", "mvc"), ("mvc", "auto"), ("mvc", "hc")):
                    for cage in scene["cages"]:
                        cage["kind"] = kind
                    scene["settings"]["join_coordinates"] = joins
                    case = os.path.join(tmp, "case.json")
                    with open(case, "w", encoding="utf-8") as f:
                        json.dump(scene, f)
                    rest_out = os.path.join(tmp, "rest.obj")
                    run(cli, "deform", case, "--out", rest_out)
                    rest = read_vertices(rest_out)
                    cages = os.path.join(tmp, "cages.obj")
                    run(cli, "cages", case, "--out", cages)
                    turned_cages = os.path.join(tmp, "turned_cages.obj")
                    with open(cages, encoding="utf-8") as f, open(
                        turned_cages, "w", encoding="utf-8"
                    ) as out:
                        for line in f:
                            if line.startswith("v "):
                                p = turn(matrix, centre, tuple(float(x) for x in line.split()[1:4]))
                                out.write("v %.17g %.17g %.17g\n" % p)
                            else:
                                out.write(line)
                    turned_out = os.path.join(tmp, "turned.obj")
                    run(cli, "deform", case, "--pose-file", turned_cages, "--out", turned_out)
                    turned = read_vertices(turned_out)
                    at_rest = max(math.dist(p, q) for p, q in zip(source, rest)) / diagonal
                    rigid = (
                        max(math.dist(turn(matrix, centre, source[i]), turned[i]) for i in used)
                        / diagonal
                    )
                    print(
                        json.dumps(
                            {
                                "mesh": name,
                                "grid": grid,
                                "leaves": kind,
                                "joins": joins,
                                "rest_error": float("%.2g" % at_rest),
                                "rigid_turn_error": float("%.2g" % rigid),
                            }
                        ),
                        flush=True,
                    )


main()

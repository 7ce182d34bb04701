#!/usr/bin/env python3
"""The paper's Fig. 10 on one of our rigs: mean value against harmonic coordinates in a concave
join cage, on a slice through the join.

Usage (matplotlib and numpy in a throw-away venv, never a project dependency):
    VENV/bin/python scripts/join_coordinates_fig10.py SCENE.json CAGE_A CAGE_B \
        path/to/starcages-cli OUT.png

The join cage of a vertex on the border of leaf cages CAGE_A and CAGE_B is their union with the
shared faces dropped (eq. 8). The script writes it as an OBJ, lays a grid of points on the plane
through the shared faces' centre that holds both cages' centres (the plane of the "L"), keeps
the points inside the join cage, and asks `starcages-cli weights` for both coordinate kinds
there. It plots the coordinate function of the join-cage vertex whose mean value coordinate
goes most negative there, with zero drawn as a contour, and prints per kind that vertex's
smallest value and share of negative points, and over every vertex the smallest coordinate and
the share of points with a negative one. Positions are the scene's cage vertices, in StarCages'
Z-up frame.
"""

import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(scene_path, names):
    with open(scene_path, encoding="utf-8") as f:
        scene = json.load(f)
    vertices = np.array(scene["cage_vertices"], dtype=float)
    cages = {c["name"]: c["faces"] for c in scene["cages"]}
    missing = [n for n in names if n not in cages]
    if missing:
        sys.exit(f"{scene_path}: no leaf cage called {', '.join(missing)}")
    return vertices, [cages[n] for n in names]


def join_cage(faces_a, faces_b):
    """The union of two cages' faces without the faces both list (their shared border)."""
    key = lambda f: tuple(sorted(f))  # noqa: E731
    keys_a = {key(f) for f in faces_a}
    keys_b = {key(f) for f in faces_b}
    shared = keys_a & keys_b
    if not shared:
        sys.exit("the two cages share no face: they have no join cage")
    faces = [f for f in faces_a + faces_b if key(f) not in shared]
    shared_vertices = sorted({v for k in shared for v in k})
    return faces, shared_vertices


def triangles(faces):
    return [(f[0], f[i], f[i + 1]) for f in faces for i in range(1, len(f) - 1)]


def inside(points, positions, tris):
    """Point-in-polyhedron by the solid angle sum (winding number), vectorised over points."""
    total = np.zeros(len(points))
    for a, b, c in tris:
        pa, pb, pc = positions[a] - points, positions[b] - points, positions[c] - points
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (pa, pb, pc))
        det = np.einsum("ij,ij->i", pa, np.cross(pb, pc))
        div = (
            la * lb * lc
            + np.einsum("ij,ij->i", pa, pb) * lc
            + np.einsum("ij,ij->i", pb, pc) * la
            + np.einsum("ij,ij->i", pc, pa) * lb
        )
        total += 2.0 * np.arctan2(det, div)
    return total / (4.0 * np.pi) > 0.5


def weights(cli, cage_obj, points_txt, kind):
    run = subprocess.run(
        [cli, "weights", "--cage", cage_obj, "--points", points_txt, "--coords", kind],
        capture_output=True,
        text=True,
    )
    if run.returncode != 0:
        sys.exit(f"starcages-cli weights --coords {kind}: {run.stderr.strip()}")
    out = run.stdout
    return np.array([p["w"] for p in json.loads(out)["points"]])


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    scene_path, name_a, name_b, cli, out_png = sys.argv[1:]
    vertices, (faces_a, faces_b) = load(scene_path, [name_a, name_b])
    faces, shared_vertices = join_cage(faces_a, faces_b)
    used = sorted({v for f in faces for v in f})
    local = {v: i for i, v in enumerate(used)}
    positions = vertices[used]
    local_faces = [[local[v] for v in f] for f in faces]
    tris = triangles(local_faces)

    # The slice: through the shared faces' centre, holding both cages' centres.
    centre = vertices[shared_vertices].mean(axis=0)
    centre_a = vertices[sorted({v for f in faces_a for v in f})].mean(axis=0)
    centre_b = vertices[sorted({v for f in faces_b for v in f})].mean(axis=0)
    u = centre_a - centre
    u /= np.linalg.norm(u)
    w = centre_b - centre
    normal = np.cross(u, w)
    if np.linalg.norm(normal) < 1e-9 * np.linalg.norm(w):
        sys.exit("the two cages' centres are in line with their shared face: no L to slice")
    normal /= np.linalg.norm(normal)
    v = np.cross(normal, u)
    extent = np.abs((positions - centre) @ np.stack([u, v]).T).max() * 1.05
    n = 160
    s = np.linspace(-extent, extent, n)
    grid_u, grid_v = np.meshgrid(s, s)
    points = centre + grid_u.reshape(-1, 1) * u + grid_v.reshape(-1, 1) * v
    keep = inside(points, positions, tris)


    with tempfile.TemporaryDirectory() as tmp:
        cage_obj = os.path.join(tmp, "join.obj")
        with open(cage_obj, "w", encoding="ascii") as f:
            for p in positions:
                f.write(f"v {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n")
            for face in local_faces:
                f.write("f " + " ".join(str(i + 1) for i in face) + "\n")
        points_txt = os.path.join(tmp, "points.txt")
        np.savetxt(points_txt, points[keep], fmt="%.17g")
        tables = {kind: weights(cli, cage_obj, points_txt, kind) for kind in ("mvc", "hc")}
    # The join-cage vertex whose mean value coordinate goes most negative on the slice.
    column = int(np.unravel_index(np.argmin(tables["mvc"]), tables["mvc"].shape)[1])
    corner_vertex = used[column]
    fields = {kind: table[:, column] for kind, table in tables.items()}
    anywhere = {
        kind: {"min_any_vertex": float(t.min()), "points_with_a_negative": float((t < 0).any(axis=1).mean())}
        for kind, t in tables.items()
    }

    # A scale twice the deepest negative value, so that the negative region shows (larger
    # values saturate); 0.05 where nothing is negative.
    deepest = min(float(f.min()) for f in fields.values())
    limit = 2.0 * -deepest if deepest < 0 else 0.05
    figure, axes = plt.subplots(1, 2, figsize=(11, 5.2), constrained_layout=True)
    report = {}
    for ax, (kind, values) in zip(axes, fields.items()):
        image = np.full(n * n, np.nan)
        image[keep] = values
        image = image.reshape(n, n)
        shown = ax.imshow(
            image,
            origin="lower",
            extent=(-extent, extent, -extent, extent),
            cmap="RdBu_r",
            vmin=-limit,
            vmax=limit,
        )
        ax.contour(grid_u, grid_v, image, levels=[0.0], colors="black", linewidths=1.2)
        corner = (vertices[corner_vertex] - centre) @ np.stack([u, v]).T
        ax.plot(corner[0], corner[1], "o", color="gold", markeredgecolor="black")
        negative = float((values < 0).mean())
        report[kind] = {"min": float(values.min()), "negative_share": negative, **anywhere[kind]}
        ax.set_title(
            f"{'mean value' if kind == 'mvc' else 'harmonic'}: min {values.min():.3g}, "
            f"{100 * negative:.1f} % of points < 0"
        )
        ax.set_xticks([])
        ax.set_yticks([])
    figure.colorbar(
        shown,
        ax=axes,
        shrink=0.8,
        label="coordinate of the marked vertex (black line: 0)",
        extend="both",
    )
    figure.suptitle(f"join cage of {name_a} and {name_b}, sliced through their shared face")
    figure.savefig(out_png, dpi=110)
    print(
        json.dumps(
            {
                "join_cage_vertices": len(used),
                "points_inside": int(keep.sum()),
                "vertex": corner_vertex,
                **report,
            }
        )
    )


if __name__ == "__main__":
    main()

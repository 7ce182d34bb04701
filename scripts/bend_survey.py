#!/usr/bin/env python3
"""Bends each named control of an auto rig the way a joint bends, and counts fold-overs.

Usage: scripts/bend_survey.py CLI SCENE [CONTROL ...] [--angle DEG] [--out DIR]

CLI is a `starcages-cli` binary; SCENE a scene with controls (`starcages-cli autorig`). Each
control (default: every control but `root`) is turned about its own pivot:
- bend+ and bend-: by +-DEG about its bend axis, the segment's direction crossed with up (Z)
  (for a segment within 30 degrees of vertical, a leg: X, across the figure);
- twist: by DEG about the segment's direction (a forearm twist).
DEG is --angle, else issue 41's poses: 30 for a head or neck, 45 for a limb's first segment
(the hip, the shoulder), 90 for the others (the knee, the elbow, the forearm's twist).
The segment's direction runs from the control's pivot to its first child's pivot, or from its
parent's pivot to its own where it has no child. Each pose is written by `deform`, compared
with the rest pose by scripts/deformation_quality.py (interior edges folded over, triangles
turned over, edges stretched over 2x), and printed as `folds/flipped/stretched`, the most an
edge is stretched, and the volume change of the part that moves / of the whole mesh (percent)
per pose, one line per control: a widened joint ring can spike the surface without folding it
(session 62: the armadillo's wrist bent 90 degrees, 53 folds but 544 edges over 2x). Axes are in
StarCages' Z-up frame, as `deform --apply` takes them. Plain Python, no packages.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plain_obj import read_obj  # noqa: E402  (beside this script)

HERE = os.path.dirname(os.path.abspath(__file__))


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def unit(v):
    length = math.sqrt(sum(x * x for x in v))
    return [x / length for x in v] if length > 0 else v


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def triangles_of(faces):
    return [(f[0], b, c) for f in faces for b, c in zip(f[1:], f[2:])]


def closed_volume(points, triangles):
    """The signed volume of `triangles`, closed by a fan from the centroid of their border."""
    edges = {}
    for t in triangles:
        for a, b in zip(t, t[1:] + t[:1]):
            key = (min(a, b), max(a, b))
            edges[key] = edges.get(key, 0) + (1 if a < b else -1)
    border = [(a, b) for t in triangles for a, b in zip(t, t[1:] + t[:1])
              if edges[(min(a, b), max(a, b))] != 0]
    corners = sorted({v for e in border for v in e})
    centre = [sum(points[v][k] for v in corners) / max(len(corners), 1) for k in range(3)]
    total = sum(dot(points[a], cross(points[b], points[c])) for a, b, c in triangles)
    total += sum(dot(points[b], cross(points[a], centre)) for a, b in border)
    return total / 6.0


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def volume_changes(rest_path, posed_path):
    """Percent volume changes of the whole mesh and of the part that moves (the triangles whose
    corners all move by over 1e-4 of the diagonal, closed across their border: the posed limb
    and the bend, as scripts/blender_armature_compare.py measures it)."""
    rest, faces = read_obj(rest_path)
    posed, _ = read_obj(posed_path)
    triangles = triangles_of(faces)
    low = [min(p[k] for p in rest) for k in range(3)]
    high = [max(p[k] for p in rest) for k in range(3)]
    diagonal = math.dist(low, high)
    moving = [math.dist(a, b) > 1e-4 * diagonal for a, b in zip(rest, posed)]
    part = [t for t in triangles if all(moving[v] for v in t)]
    whole = 100.0 * (closed_volume(posed, triangles) / closed_volume(rest, triangles) - 1.0)
    if not part:
        return whole, 0.0
    moved = 100.0 * (closed_volume(posed, part) / closed_volume(rest, part) - 1.0)
    return whole, moved


def quality(rest, posed):
    out = subprocess.run(
        [sys.executable, os.path.join(HERE, "deformation_quality.py"), rest, posed],
        capture_output=True, text=True, check=True,
    ).stdout
    report = json.loads(out)
    whole, moved = volume_changes(rest, posed)
    return (f"{report['folds']}/{report['flipped']}/{report['edges_stretched_over_2x']}"
            f" {report['edge_ratio_max']:.2f}x {moved:+.2f}%/{whole:+.2f}%")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("cli")
    parser.add_argument("scene")
    parser.add_argument("controls", nargs="*")
    parser.add_argument("--angle", type=float, help="degrees for every control (see above)")
    parser.add_argument("--out", help="folder for the posed OBJ files (default: a temporary one)")
    args = parser.parse_args()
    info = json.loads(
        subprocess.run([args.cli, "info", args.scene, "--json"], capture_output=True,
                       text=True, check=True).stdout
    )
    controls = {c["name"]: c for c in info.get("controls", [])}
    children = {}
    for c in info.get("controls", []):
        if c.get("parent"):
            children.setdefault(c["parent"], []).append(c["name"])
    names = args.controls or [n for n in controls if n != "root"]
    folder = args.out or tempfile.mkdtemp(prefix="bend_survey_")
    os.makedirs(folder, exist_ok=True)
    rest = os.path.join(folder, "rest.obj")
    subprocess.run([args.cli, "deform", args.scene, "--out", rest], capture_output=True,
                   check=True)
    for name in names:
        control = controls.get(name)
        if control is None or not control.get("pivot"):
            print(f"{name}: no such control with a pivot", file=sys.stderr)
            continue
        pivot = control["pivot"]
        if name in children:
            direction = sub(controls[children[name][0]]["pivot"], pivot)
        elif control.get("parent") in controls:
            direction = sub(pivot, controls[control["parent"]]["pivot"])
        else:
            continue
        direction = unit(direction)
        if abs(direction[2]) > math.cos(math.radians(30)):
            bend = [1.0, 0.0, 0.0]
        else:
            bend = unit(cross(direction, [0.0, 0.0, 1.0]))
        if args.angle is not None:
            degrees = args.angle
        elif name.startswith(("head", "neck")):
            degrees = 30.0
        elif name.endswith(".1"):
            degrees = 45.0
        else:
            degrees = 90.0
        results = []
        for label, axis, angle in [
            ("bend+", bend, degrees),
            ("bend-", bend, -degrees),
            ("twist", direction, degrees),
        ]:
            posed = os.path.join(folder, f"{name}_{label}.obj")
            edit = f"{name}: rotate {axis[0]:.5f} {axis[1]:.5f} {axis[2]:.5f} {angle}"
            run = subprocess.run([args.cli, "deform", args.scene, "--apply", edit, "--out",
                                  posed], capture_output=True, text=True)
            if run.returncode != 0:
                results.append(f"{label} failed: {run.stderr.strip()}")
                continue
            results.append(f"{label} {quality(rest, posed)}")
        print(f"{name} ({degrees:g} deg): " + " | ".join(results), flush=True)


if __name__ == "__main__":
    main()

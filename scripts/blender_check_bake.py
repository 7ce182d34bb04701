"""Checks StarCages' baked animation in Blender, the client artists use.

For a scene with keys, this bakes PC2, MDD and GLB with `starcages-cli bake`, writes the mesh
at sample frames with `starcages-cli deform --frame`, then in Blender:

* imports the first frame's OBJ (axes as they are), adds a Mesh Cache modifier per cache
  (Frame Start = the bake's first frame, Frame time mode) and compares every sampled frame's
  evaluated mesh with `deform --frame`;
* imports the GLB with Blender's glTF importer (shape keys with animated values) and compares
  the same frames, turned back from Blender's Z-up to the file's Y-up.

Every difference must stay under 1e-4 of the mesh's bounding-box diagonal (float32 caches).

Blender is not a project dependency: install it in a throw-away virtual environment outside
the project (`python3.11 -m venv /tmp/bpy && /tmp/bpy/bin/pip install bpy`), then

    /tmp/bpy/bin/python scripts/blender_check_bake.py SCENE.json OUT_DIR [--cli PATH] [--frames A..B]

It prints one line per format and frame, and exits with status 1 when a frame is off.
"""

import argparse
import math
import subprocess
import sys
from pathlib import Path


def read_obj_vertices(path):
    vertices = []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                x, y, z = (float(t) for t in line.split()[1:4])
                vertices.append((x, y, z))
    return vertices


def diagonal(points):
    lo = [min(p[k] for p in points) for k in range(3)]
    hi = [max(p[k] for p in points) for k in range(3)]
    return math.sqrt(sum((h - l) ** 2 for l, h in zip(lo, hi)))


def largest_difference(a, b):
    if len(a) != len(b):
        return float("inf")
    return max(max(abs(p[k] - q[k]) for k in range(3)) for p, q in zip(a, b))


def evaluated_vertices(bpy, obj, to_file=lambda p: p):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    out = [to_file(tuple(v.co)) for v in mesh.vertices]
    evaluated.to_mesh_clear()
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--cli", default="target/release/starcages-cli")
    parser.add_argument("--frames", default=None, help="A..B (default: the scene's range)")
    parser.add_argument("--check-every", type=int, default=5, help="compare every Nth frame")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    def cli(*words):
        subprocess.run([args.cli, *map(str, words)], check=True, capture_output=True)

    frames = ["--frames", args.frames] if args.frames else []
    bakes = {}
    for ext in ["pc2", "mdd", "glb"]:
        path = args.out / f"bake.{ext}"
        cli("bake", args.scene, "--out", path, "--cache", *frames)
        bakes[ext] = path
    # The sampled frames: read back from the PC2 header.
    import struct

    with open(bakes["pc2"], "rb") as f:
        header = f.read(32)
    _, _, points, start, step, samples = struct.unpack("<12siiffi", header)
    first = int(round(start))
    checked = list(range(first, first + samples, max(1, args.check_every)))
    if checked[-1] != first + samples - 1:
        checked.append(first + samples - 1)
    expected = {}
    for frame in checked:
        obj = args.out / f"frame_{frame}.obj"
        cli("deform", args.scene, "--frame", frame, "--out", obj, "--cache")
        expected[frame] = read_obj_vertices(obj)
    base_obj = args.out / f"frame_{first}.obj"
    tolerance = 1e-4 * diagonal(expected[first])

    import bpy

    failures = 0

    def report(kind, frame, got):
        nonlocal failures
        error = largest_difference(got, expected[frame])
        ok = error <= tolerance
        failures += not ok
        print(f"{kind} frame {frame}: largest difference {error:.3g} "
              f"(tolerance {tolerance:.3g}) {'ok' if ok else 'OFF'}")

    for kind in ["pc2", "mdd"]:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.ops.wm.obj_import(filepath=str(base_obj), forward_axis="Y", up_axis="Z")
        obj = bpy.context.selected_objects[0]
        modifier = obj.modifiers.new("cache", "MESH_CACHE")
        modifier.cache_format = kind.upper()
        modifier.filepath = str(bakes[kind])
        modifier.frame_start = first
        modifier.time_mode = "FRAME"
        modifier.play_mode = "SCENE"
        for frame in checked:
            bpy.context.scene.frame_set(frame)
            report(kind, frame, evaluated_vertices(bpy, obj))

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(bakes["glb"]))
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    obj = meshes[0]
    keys = obj.data.shape_keys
    print(f"glb: {len(keys.key_blocks) - 1 if keys else 0} shape keys")
    # Blender turns glTF's Y-up into Z-up: (x, y, z) -> (x, -z, y); turn it back.
    to_file = lambda p: (p[0], p[2], -p[1])
    # Bakes store scene time (frame / fps), so frame N should play at Blender frame N: check
    # that on the sample farthest from the first (the first may equal the rest shape, which
    # every frame before the animation shows), trying neighbours to say how far off it is.
    probe = max(checked, key=lambda f: largest_difference(expected[f], expected[first]))
    offset = None
    for candidate in [0, -1, 1, -2, 2]:
        bpy.context.scene.frame_set(candidate + probe)
        got = evaluated_vertices(bpy, obj, to_file)
        if largest_difference(got, expected[probe]) <= tolerance:
            offset = candidate
            break
    print(f"glb: frame N plays at Blender frame N + {offset}")
    if offset != 0:
        failures += 1
    else:
        for frame in checked:
            bpy.context.scene.frame_set(offset + frame)
            report("glb", frame, evaluated_vertices(bpy, obj, to_file))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

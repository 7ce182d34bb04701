#!/usr/bin/env python3
"""Every mesh format StarCages reads, written by Blender from one awkward scene, read back by
Blender's importers and by StarCages: are the vertices where Blender puts them, at rest, with
outward winding?

The scene: a parent with a child under it (parents), a non-uniformly scaled box, a mirrored box
(negative scale), two linked duplicates of one mesh, and a limb skinned to a rotated, scaled
and moved armature. Written as GLB, .gltf (+ .bin), OBJ, FBX, PLY and STL; the GLB is also
packed by gltfpack (quantized, and -cc meshopt-compressed) when GLTFPACK is given.

Usage (Blender 5 as the `bpy` package in a throw-away venv, never a project dependency):
    VENV/bin/python scripts/blender_roundtrip_formats.py OUT_DIR STARCAGES_CLI [GLTFPACK]

Per file it prints: vertices StarCages read, the largest distance from one of them to the
nearest vertex of Blender's import (and back), as a share of the scene's diagonal, and the
signed volume of StarCages' mesh (positive: outward winding). A file StarCages refuses prints
its message. 2026-11-26 (Blender 5.0.1, gltfpack 0.24): GLB, .gltf, OBJ and gltfpack's GLB
within 7e-8 of the diagonal, -cc within 3e-5 (its 14-bit position quantization), PLY and STL
exact (STL keeps the file's three corners per triangle: 1,998 vertices where Blender merges to
347); FBX within 8e-8 with outward winding (1,128 vertices: Blender writes a normal per
polygon corner and the flat-shaded primitives split at their hard edges; welded for binding). Blender's PLY export writes the mirrored cone inside out
(its volume counts negative in ours and in Blender's import alike). Blender cannot import EXT_meshopt_compression: the `-cc` file is compared with
Blender's import of the GLB it was packed from. Positions are compared in the file's own axes: glTF, OBJ and FBX are Y-up (Blender's
exporters turn its Z-up world), PLY and STL Z-up as Blender writes them (read with --up z).
"""

import json
import math
import os
import subprocess
import sys

import bpy
from plain_obj import read_obj  # noqa: E402  (beside this script)


def build_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Parent and child: the child's world = parent × local.
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.0))
    parent = bpy.context.active_object
    parent.name = "parent"
    parent.rotation_euler = (0.0, 0.0, math.radians(20))
    parent.location = (0.0, 0.0, 0.5)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.4, location=(0, 0, 0))
    child = bpy.context.active_object
    child.name = "child"
    child.parent = parent
    child.location = (1.5, 0.0, 0.0)
    # Non-uniform scale.
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-2.0, 0.0, 0.5))
    stretched = bpy.context.active_object
    stretched.name = "stretched"
    stretched.scale = (0.5, 1.5, 0.25)
    # Mirrored (negative determinant).
    bpy.ops.mesh.primitive_cone_add(vertices=12, radius1=0.4, depth=0.8, location=(0, 2.0, 0.5))
    mirrored = bpy.context.active_object
    mirrored.name = "mirrored"
    mirrored.scale = (-1.0, 1.0, 1.0)
    # Linked duplicates: two objects, one mesh.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=12, ring_count=6, radius=0.3, location=(0, -2, 0.5))
    first = bpy.context.active_object
    first.name = "linked_a"
    second = first.copy()
    second.name = "linked_b"
    second.location = (1.0, -2.0, 0.8)
    bpy.context.scene.collection.objects.link(second)
    # A limb skinned to a transformed armature.
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    limb = bpy.context.active_object
    limb.name = "limb"
    limb.scale = (0.3, 0.3, 2.0)
    bpy.ops.object.transform_apply(scale=True)
    limb.location = (0.0, 0.0, 1.0)
    bpy.ops.object.transform_apply(location=True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=4)
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.armature_add(location=(0.0, 0.0, 0.0))
    armature = bpy.context.active_object
    bpy.ops.object.mode_set(mode="EDIT")
    bones = armature.data.edit_bones
    bones[0].head, bones[0].tail = (0, 0, 0), (0, 0, 1)
    upper = bones.new("upper")
    upper.head, upper.tail, upper.parent = (0, 0, 1), (0, 0, 2), bones[0]
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.select_all(action="DESELECT")
    limb.select_set(True)
    armature.select_set(True)
    bpy.context.view_layer.objects.active = armature
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    armature.rotation_euler = (math.radians(90), 0.0, math.radians(30))
    armature.scale = (1.0, 0.5, 1.0)
    armature.location = (3.0, 1.0, 0.2)
    bpy.ops.object.select_all(action="SELECT")


def export_all(out):
    files = {}
    bpy.ops.export_scene.gltf(filepath=f"{out}/scene.glb", export_format="GLB")
    files["glb"] = "scene.glb"
    bpy.ops.export_scene.gltf(filepath=f"{out}/scene.gltf", export_format="GLTF_SEPARATE")
    files["gltf"] = "scene.gltf"
    bpy.ops.wm.obj_export(filepath=f"{out}/scene.obj", export_materials=False)
    files["obj"] = "scene.obj"
    bpy.ops.export_scene.fbx(filepath=f"{out}/scene.fbx")
    files["fbx"] = "scene.fbx"
    bpy.ops.wm.ply_export(filepath=f"{out}/scene.ply")
    files["ply"] = "scene.ply"
    bpy.ops.wm.stl_export(filepath=f"{out}/scene.stl")
    files["stl"] = "scene.stl"
    return files


def imported_positions(path):
    """World positions of every mesh vertex after Blender's importer reads `path`."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = os.path.splitext(path)[1]
    if ext in (".glb", ".gltf"):
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path)
    elif ext == ".fbx":
        bpy.ops.import_scene.fbx(filepath=path)
    elif ext == ".ply":
        bpy.ops.wm.ply_import(filepath=path)
    elif ext == ".stl":
        bpy.ops.wm.stl_import(filepath=path)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    points = []
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        # The glTF importer adds a sphere mesh as the bones' display shape: not scene content.
        if obj.users_collection and not obj.visible_get():
            continue
        evaluated = obj.evaluated_get(depsgraph)
        for v in evaluated.data.vertices:
            w = evaluated.matrix_world @ v.co
            points.append((w.x, w.y, w.z))
    return points


def in_file_axes(points, ext):
    """Blender's Z-up world in the file's own axes (glTF, OBJ, FBX: Y-up)."""
    if ext in (".ply", ".stl"):
        return points
    return [(x, z, -y) for x, y, z in points]


def signed_volume(vertices, faces):
    total = 0.0
    for f in faces:
        a = vertices[f[0]]
        for k in range(1, len(f) - 1):
            b, c = vertices[f[k]], vertices[f[k + 1]]
            total += (
                a[0] * (b[1] * c[2] - b[2] * c[1])
                - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
            ) / 6.0
    return total


def farthest_nearest(points, others):
    """The largest distance from a point of `points` to its nearest in `others` (a grid)."""
    cell = 0.05
    grid = {}
    for q in others:
        grid.setdefault(tuple(int(math.floor(c / cell)) for c in q), []).append(q)
    worst = 0.0
    for p in points:
        key = tuple(int(math.floor(c / cell)) for c in p)
        best = math.inf
        for ring in range(0, 40):
            for dx in range(-ring, ring + 1):
                for dy in range(-ring, ring + 1):
                    for dz in range(-ring, ring + 1):
                        if max(abs(dx), abs(dy), abs(dz)) != ring:
                            continue
                        for q in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ()):
                            best = min(best, math.dist(p, q))
            if best <= ring * cell:
                break
        worst = max(worst, best)
    return worst


def starcages_positions(cli, path, out):
    ext = os.path.splitext(path)[1]
    scene = f"{out}/{os.path.basename(path)}.json"
    deformed = f"{out}/{os.path.basename(path)}.ours.obj"
    up = ["--up", "z"] if ext in (".ply", ".stl") else []
    made = subprocess.run([cli, "autocage", path, "--out", scene, *up], capture_output=True, text=True)
    if made.returncode != 0:
        return None, made.stderr.strip()
    # At rest the deformation is the mesh as read, in the file's axes.
    done = subprocess.run([cli, "deform", scene, "--out", deformed], capture_output=True, text=True)
    if done.returncode != 0:
        return None, done.stderr.strip()
    return read_obj(deformed), None


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, cli = os.path.abspath(sys.argv[1]), sys.argv[2]
    gltfpack = sys.argv[3] if len(sys.argv) > 3 else None
    os.makedirs(out, exist_ok=True)
    build_scene()
    files = export_all(out)
    if gltfpack:
        for name, options in (("packed.glb", []), ("packed_cc.glb", ["-cc"])):
            subprocess.run([gltfpack, "-i", f"{out}/scene.glb", "-o", f"{out}/{name}", *options],
                           check=True, capture_output=True)
            files[name] = name
    report = []
    for label, name in files.items():
        path = f"{out}/{name}"
        ext = os.path.splitext(path)[1]
        # Blender 5 cannot import EXT_meshopt_compression: the -cc file is compared with
        # Blender's import of the GLB it was packed from.
        source = f"{out}/scene.glb" if name == "packed_cc.glb" else path
        reference = in_file_axes(imported_positions(source), ext)
        ours, error = starcages_positions(cli, path, out)
        if ours is None:
            report.append({"file": name, "starcages": "refused", "message": error})
            continue
        vertices, faces = ours
        lo = [min(p[i] for p in reference) for i in range(3)]
        hi = [max(p[i] for p in reference) for i in range(3)]
        diagonal = math.dist(lo, hi)
        report.append({
            "file": name,
            "vertices_ours": len(vertices),
            "vertices_blender": len(reference),
            "ours_to_blender": farthest_nearest(vertices, reference) / diagonal,
            "blender_to_ours": farthest_nearest(reference, vertices) / diagonal,
            "signed_volume": signed_volume(vertices, faces),
        })
    print(json.dumps(report, indent=1))


main()

#!/usr/bin/env python3
"""A skinned limb under a rotated, scaled and moved armature, written by Blender as GLB, and
where Blender's own importer places its vertices: the reference StarCages' glTF reader is
checked against (skins place meshes by their joints, not by the mesh node).

Usage (Blender 5 as the `bpy` package in a throw-away venv, never a project dependency):
    VENV/bin/python scripts/blender_skinned_gltf.py OUT_DIR
Writes OUT_DIR/skinned.glb and prints JSON: the re-imported mesh's evaluated vertex positions,
world space, in glTF axes (Y up), as Blender's importer gives them (split at sharp edges).
Compare with StarCages' reading of the same file:
    starcages-cli autocage OUT_DIR/skinned.glb --out s.json
    starcages-cli deform s.json --out ours.obj       # at rest, in the file's axes
every vertex of ours.obj lies on one of Blender's (2026-11-25: within 9e-8 of the diagonal).
"""

import json
import math
import sys

import bpy


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # A limb: a subdivided bar along z, two bones.
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    limb = bpy.context.active_object
    limb.name = "limb"
    limb.scale = (0.3, 0.3, 2.0)
    bpy.ops.object.transform_apply(scale=True)
    limb.location = (0.0, 0.0, 1.0)
    bpy.ops.object.transform_apply(location=True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.subdivide(number_cuts=6)
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.armature_add(location=(0.0, 0.0, 0.0))
    armature = bpy.context.active_object
    bpy.ops.object.mode_set(mode="EDIT")
    bones = armature.data.edit_bones
    lower = bones[0]
    lower.head, lower.tail = (0, 0, 0), (0, 0, 1)
    upper = bones.new("upper")
    upper.head, upper.tail, upper.parent = (0, 0, 1), (0, 0, 2), lower
    bpy.ops.object.mode_set(mode="OBJECT")
    limb.select_set(True)
    armature.select_set(True)
    bpy.context.view_layer.objects.active = armature
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    # The armature object rotated, scaled (non-uniformly) and moved, as FBX-born rigs are.
    armature.rotation_euler = (math.radians(90), 0.0, math.radians(30))
    armature.scale = (0.01, 0.02, 0.01)
    armature.location = (3.0, -2.0, 1.0)
    path = f"{out}/skinned.glb"
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    # The skinned mesh only (the importer adds a sphere mesh as the bones' display shape).
    meshes = [
        o
        for o in bpy.context.scene.objects
        if o.type == "MESH" and any(m.type == "ARMATURE" for m in o.modifiers)
    ]
    positions = []
    for obj in meshes:
        evaluated = obj.evaluated_get(depsgraph)
        for v in evaluated.data.vertices:
            w = evaluated.matrix_world @ v.co
            positions.append([w.x, w.z, -w.y])  # Blender Z-up to glTF Y-up
    print(json.dumps({"file": path, "positions": positions}))


main()

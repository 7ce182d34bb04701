"""Tries the Blender extension as an artist would, headless through `bpy`: imports a mesh
(e.g. ../shared/meshes/horse.obj), auto-rigs it with the extension, keys a leg control at
frames 1 and 24, and renders frame 12 (Workbench) beside the rest pose, for looking at.

    /tmp/bpyvenv/bin/python scripts/blender_try_mesh.py MESH.obj OUT_FOLDER
"""

import math
import sys
import time
from pathlib import Path

import bpy
from blender_common import import_mesh, load_extension, render_frames
from mathutils import Vector

source, out = sys.argv[-2], Path(sys.argv[-1])
out.mkdir(parents=True, exist_ok=True)
ext = load_extension()

obj = import_mesh(source)
start = time.perf_counter()
assert bpy.ops.starcages.autorig(detail=3) == {"FINISHED"}
print(f"auto rig and bind: {time.perf_counter() - start:.1f} s, {len(obj.data.vertices)} vertices")
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
print("controls:", sorted(controls))
legs = sorted(n for n in controls if n.startswith("leg") and n.endswith(".2"))
leg = legs[0] if legs else sorted(n for n in controls if n.startswith("leg"))[0]
scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 24
control = controls[leg]
control.keyframe_insert("rotation_euler", frame=1)
control.rotation_euler.y += math.radians(70)
control.keyframe_insert("rotation_euler", frame=24)

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
centre = sum(corners, Vector()) / 8
size = max((a - b).length for a in corners for b in corners)
camera.location = centre + Vector((0.25 * size, -1.5 * size, 0.2 * size))
camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
render_frames(scene, out, f"{Path(source).stem}_{leg}", (1, 12, 24), (640, 480))
print("bent", leg, "rendered to", out)

"""A two-pose walk keyed in Blender on an auto rig, baked and looked at, as issue 41 asks a
user to try: imports a mesh (a biped or a quadruped from ../shared/meshes/), auto-rigs it with
the extension, keys the legs' hip and knee controls (and the arms' elbows) at frames 1, 13 and
25 in two opposite poses, bakes to a point cache played by Mesh Cache (the rig removed), and
renders frames 1, 7 and 13 (Workbench).

    /tmp/bpyvenv/bin/python scripts/blender_walk.py MESH.obj OUT_FOLDER
"""

import math
import sys
from pathlib import Path

import bpy
from blender_common import import_mesh, load_extension, render_frames
from mathutils import Vector

source, out = sys.argv[-2], Path(sys.argv[-1])
out.mkdir(parents=True, exist_ok=True)
ext = load_extension()

obj = import_mesh(source)
assert bpy.ops.starcages.autorig(detail=3) == {"FINISHED"}
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
print("controls:", sorted(controls))
corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
size = [max(c[i] for c in corners) - min(c[i] for c in corners) for i in range(3)]
legs = sorted({n.rsplit(".", 1)[0] for n in controls if n.startswith("leg")})
arms = sorted({n.rsplit(".", 1)[0] for n in controls if n.startswith("arm")})
# A quadruped walks along its long horizontal axis (legs swing about the other one); a biped's
# long horizontal axis is across its shoulders, the axis its legs swing about.
widest = 0 if size[0] > size[1] else 1
swing = widest if arms else 1 - widest
print("swing about", "xyz"[swing])


def turn(name, degrees, frame):
    empty = controls.get(name)
    if empty is None:
        return False
    empty.rotation_euler = (0.0, 0.0, 0.0)
    empty.rotation_euler[swing] = math.radians(degrees)
    empty.keyframe_insert("rotation_euler", frame=frame)
    return True


print("legs:", legs, "arms:", arms)
for frame, sign in ((1, 1), (13, -1), (25, 1)):
    for k, leg in enumerate(legs):
        side = 1 if (k % 2 == 0) else -1
        turn(f"{leg}.1", 25 * sign * side, frame)  # hip
        turn(f"{leg}.2", -35 if sign * side > 0 else 0, frame)  # knee
    for k, arm in enumerate(arms):
        side = -1 if (k % 2 == 0) else 1
        turn(f"{arm}.1", 20 * sign * side, frame)  # shoulder
        turn(f"{arm}.2", 45, frame)  # elbow
scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 25
stem = Path(source).stem
bpy.ops.starcages.bake(filepath=str(out / f"{stem}_walk.pc2"), remove_rig=True)

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
centre = sum(corners, Vector()) / 8
extent = max(size)
# From the side: along the swing axis, a little ahead and above.
view = Vector((0.0, 0.0, 0.15 * extent))
view[swing] = -2.4 * extent
view[1 - swing] = 0.4 * extent
camera.location = centre + view
camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
render_frames(scene, out, f"{stem}_walk", (1, 7, 13), (480, 480))
print("walk baked and rendered to", out)

"""Times the Blender extension headless through `bpy` on a real mesh (e.g.
../shared/meshes/armadillo.obj): the auto rig and bind, one control drag step (a new angle,
the depsgraph updated, the mesh deformed through the shape key) and keyed playback (frame_set
over 24 frames of a keyed control), as the issue's figures ask.

    /tmp/bpyvenv/bin/python scripts/blender_bench.py MESH.obj
"""

import math
import sys
import time
from pathlib import Path

import bpy
from blender_common import import_mesh, load_extension

ext = load_extension()

obj = import_mesh(sys.argv[-1])
start = time.perf_counter()
bpy.ops.starcages.autorig(detail=3)
rig_seconds = time.perf_counter() - start
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
name = sorted(n for n in controls if controls[n].parent is not None)[0]
control = controls[name]
steps = 30
start = time.perf_counter()
for k in range(steps):
    control.rotation_euler.x = math.radians(k)
    bpy.context.view_layer.update()
drag = (time.perf_counter() - start) / steps
scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 24
control.rotation_euler.x = 0.0
control.keyframe_insert("rotation_euler", frame=1)
control.rotation_euler.x = math.radians(60)
control.keyframe_insert("rotation_euler", frame=24)
start = time.perf_counter()
for frame in range(1, 25):
    scene.frame_set(frame)
play = (time.perf_counter() - start) / 24
print(
    f"{Path(sys.argv[-1]).name}: {len(obj.data.vertices)} vertices, {len(controls)} controls; "
    f"auto rig + bind {rig_seconds:.2f} s; control drag {1 / drag:.0f} updates/s "
    f"({1e3 * drag:.1f} ms); keyed playback {1 / play:.0f} frames/s ({1e3 * play:.1f} ms), "
    f"control {name}"
)

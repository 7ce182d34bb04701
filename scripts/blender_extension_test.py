"""Tries the Blender extension headless through the `bpy` package (a throw-away venv with the
starcages wheel installed, or the module scripts/test.sh builds on PYTHONPATH; never part of the
project's dependencies):

    /tmp/bpyvenv/bin/pip install --force-reinstall --no-deps target/wheels/starcages-*.whl
    /tmp/bpyvenv/bin/python scripts/blender_extension_test.py target/starcages-cli OUT_FOLDER

It rigs the creature demo's mesh with the extension's Auto rig, bends a leg control, and checks
that the evaluated mesh equals `starcages-cli deform` of the exported scene (to 1e-6 of the
diagonal); saves and reopens the .blend and checks the rig is still live; renders a frame
(Workbench) to OUT_FOLDER/blender_bent_leg.png; removes the rig and checks the mesh is back.
"""

import math
import subprocess
import sys
from pathlib import Path

import bpy
from blender_common import load_extension
import numpy as np

import starcages as sc

CLI, OUT = sys.argv[-2], Path(sys.argv[-1])
OUT.mkdir(parents=True, exist_ok=True)

ext = load_extension()


def evaluated(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(depsgraph).data
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def cli_deform(scene_file, out):
    subprocess.run([CLI, "deform", str(scene_file), "--out", str(out)], check=True, capture_output=True)
    return sc.read_mesh(out)[0]


def paired(ours_rest, theirs_rest):
    """Index of each of our vertices among the CLI's (its OBJ reads back in face order), by
    rest position: both sorted along their coordinates rounded to 1e-4 of the diagonal, which
    pairs them when both round alike (the CLI writes the positions it read); otherwise each
    vertex is looked up in a grid of such cells, the neighbouring cells searched."""
    cell = 1e-4 * float(np.linalg.norm(ours_rest.max(axis=0) - ours_rest.min(axis=0)))
    assert len(ours_rest) == len(theirs_rest), "the CLI wrote another vertex count"

    def order(points):
        key = np.round(points / cell).astype(np.int64)
        return np.lexsort((key[:, 2], key[:, 1], key[:, 0]))

    out = np.empty(len(ours_rest), dtype=np.int64)
    out[order(ours_rest)] = order(theirs_rest)
    if np.linalg.norm(theirs_rest[out] - ours_rest, axis=1).max() < 1e-5 * cell * 1e4:
        return out
    grid = {}
    for j, p in enumerate(theirs_rest):
        grid.setdefault(tuple(np.floor(p / cell).astype(int)), []).append(j)
    for i, p in enumerate(ours_rest):
        c = np.floor(p / cell).astype(int)
        best, best_d = -1, np.inf
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for j in grid.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        d = np.linalg.norm(theirs_rest[j] - p)
                        if d < best_d:
                            best, best_d = j, d
        assert best_d < 1e-5 * cell * 1e4, f"vertex {i} has no partner"
        out[i] = best
    assert len(set(out.tolist())) == len(out), "two vertices paired with one"
    return out


bpy.ops.wm.read_factory_settings(use_empty=True)
demo = sc.demo("creature")
vertices = demo.to_scene_axes(demo.mesh_vertices)
mesh = bpy.data.meshes.new("creature")
mesh.from_pydata(vertices.tolist(), [], demo.mesh_triangles.tolist())
obj = bpy.data.objects.new("creature", mesh)
bpy.context.scene.collection.objects.link(obj)
bpy.context.view_layer.objects.active = obj
obj.select_set(True)
original = evaluated(obj)
diagonal = float(np.linalg.norm(original.max(axis=0) - original.min(axis=0)))

assert bpy.ops.starcages.autorig(detail=3) == {"FINISHED"}
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
print("controls:", sorted(controls))
assert controls, "no controls"
assert np.abs(evaluated(obj) - original).max() < 1e-5 * diagonal, "not exact at rest"
bpy.ops.starcages.export_scene(filepath=str(OUT / "rest.json"))

# Blender's undo of a control move restores the mesh with it (undo replaces the objects:
# fetch them again).
some = next(e for e in controls.values() if e.parent is not None)
bpy.ops.ed.undo_push(message="rigged")
some.rotation_euler.x += math.radians(40)
bpy.context.view_layer.update()
bpy.ops.ed.undo_push(message="turn a control")
assert np.abs(evaluated(obj) - original).max() > 1e-3 * diagonal
assert bpy.ops.ed.undo() == {"FINISHED"}
bpy.context.view_layer.update()
obj = bpy.data.objects["creature"]
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
assert np.abs(evaluated(obj) - original).max() < 1e-5 * diagonal, "undo left the mesh turned"
print("undo of a control move: the mesh is back at rest")

# Swing a leg (a control with a parent) 45 degrees at its joint.
leg = sorted(name for name, e in controls.items() if e.parent is not None and name.startswith("leg"))
name = leg[0] if leg else next(n for n, e in controls.items() if e.parent is not None)
controls[name].rotation_euler.y += math.radians(45)
bpy.context.view_layer.update()
bent = evaluated(obj)
moved = np.abs(bent - original).max()
print(f"bent {name}: the mesh moved up to {moved / diagonal:.3f} of the diagonal")
assert moved > 1e-3 * diagonal, "the control did not deform the mesh (handler not called)"

bpy.ops.starcages.export_scene(filepath=str(OUT / "bent.json"))
rest_cli = cli_deform(OUT / "rest.json", OUT / "rest.obj")
bent_cli = cli_deform(OUT / "bent.json", OUT / "bent.obj")
exported = sc.Scene.load(OUT / "bent.json")
order = paired(exported.mesh_vertices, rest_cli)
welded_of = ext._welded_of(vertices)
expected = bent_cli[order][welded_of]
error = np.abs(bent - expected).max() / diagonal
print(f"Blender's evaluated mesh against starcages-cli deform of the exported scene: {error:.2e} of the diagonal")
assert error <= 1e-6

# Save, reopen: still live.
blend = OUT / "rigged.blend"
bpy.ops.wm.save_as_mainfile(filepath=str(blend))
bpy.ops.wm.open_mainfile(filepath=str(blend))
obj = bpy.data.objects["creature"]
controls = {e["starcages_control"]: e for e in bpy.data.objects if e.get("starcages_rig") == obj.name}
reopened = evaluated(obj)
print("reopened: from bent", np.abs(reopened - bent).max() / diagonal, "from rest", np.abs(reopened - original).max() / diagonal,
      "keys", [k.name for k in obj.data.shape_keys.key_blocks] if obj.data.shape_keys else None)
assert np.abs(reopened - bent).max() < 1e-5 * diagonal, "the reopened file lost the pose"
controls[name].rotation_euler.y -= math.radians(45)
bpy.context.view_layer.update()
assert np.abs(evaluated(obj) - original).max() < 1e-5 * diagonal, "not live after reopening"
controls[name].rotation_euler.y += math.radians(45)
bpy.context.view_layer.update()

# Speed: one control drag step (a new angle, the depsgraph updated, the handler deforming the
# mesh through the shape key), as a drag or playback of a keyed control does each frame.
import time

steps = 30
start = time.perf_counter()
for k in range(steps):
    controls[name].rotation_euler.y = math.radians(45 + k)
    bpy.context.view_layer.update()
seconds = (time.perf_counter() - start) / steps
print(f"control drag: {1 / seconds:.0f} updates per second ({1e3 * seconds:.1f} ms each, {len(vertices)} vertices)")
controls[name].rotation_euler.y = math.radians(45)
bpy.context.view_layer.update()

# A look at it (Workbench).
scene = bpy.context.scene
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
centre = (original.max(axis=0) + original.min(axis=0)) / 2
camera.location = (centre[0] + 0.3 * diagonal, centre[1] - 1.6 * diagonal, centre[2] + 0.3 * diagonal)
from mathutils import Vector

camera.rotation_euler = (Vector(centre.tolist()) - camera.location).to_track_quat("-Z", "Y").to_euler()
for o in bpy.data.objects:
    if o.get("starcages_cages") or o.get("starcages_rig"):
        o.hide_render = True
scene.render.engine = "BLENDER_WORKBENCH"
scene.render.resolution_x, scene.render.resolution_y = 640, 480
scene.render.filepath = str(OUT / "blender_bent_leg.png")
bpy.ops.render.render(write_still=True)

# Edit Mode on the cage object: a cage vertex moved by hand moves the mesh, live, on top of
# the controls' pose, and the export carries it (the CLI deforms it the same).
import bmesh

cage_obj = next(o for o in bpy.data.objects if o.get("starcages_cages") == obj.name)
before = evaluated(obj)
bpy.context.view_layer.objects.active = cage_obj
bpy.ops.object.mode_set(mode="EDIT")
edit = bmesh.from_edit_mesh(cage_obj.data)
edit.verts.ensure_lookup_table()
# The highest vertex of the leaf cages (a control's vertex would move those it owns).
leaf_vertices = sorted({v for c in exported.leaf_cages for f in c["faces"] for v in f})
corner = leaf_vertices[int(np.argmax(exported.cage_vertices[leaf_vertices, 2]))]
edit.verts[corner].co.z += 0.05 * diagonal
bmesh.update_edit_mesh(cage_obj.data)
bpy.context.view_layer.update()
# (While another object is in Edit Mode, read the shape key the viewport draws.)
key = obj.data.shape_keys.key_blocks["StarCages"]
live = np.empty(len(key.data) * 3)
key.data.foreach_get("co", live)
moved = np.abs(live.reshape(-1, 3) - before).max() / diagonal
print(f"cage vertex {corner} moved in Edit Mode: the mesh moved {moved:.2e} of the diagonal, live")
assert moved > 1e-4
bpy.ops.object.mode_set(mode="OBJECT")
bpy.context.view_layer.objects.active = obj
bpy.ops.starcages.export_scene(filepath=str(OUT / "hand.json"))
hand = cli_deform(OUT / "hand.json", OUT / "hand.obj")[order][welded_of]
assert np.abs(evaluated(obj) - hand).max() <= 1e-6 * diagonal, "the hand move is not the CLI's"
cage_obj.data.vertices[corner].co.z -= 0.05 * diagonal
bpy.context.view_layer.objects.active = cage_obj
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.object.mode_set(mode="OBJECT")
del obj["starcages_offsets"]
bpy.context.view_layer.objects.active = obj
bpy.context.view_layer.update()
assert np.abs(evaluated(obj) - before).max() <= 1e-6 * diagonal

# Import, then export: the same scene (a scene at rest: an imported scene's controls start at
# rest).
imported_file = OUT / "rest.json"
bpy.ops.starcages.import_scene(filepath=str(imported_file))
copy = bpy.data.objects["rest"]
bpy.context.view_layer.objects.active = copy
bpy.ops.starcages.export_scene(filepath=str(OUT / "again.json"))
first, again = sc.Scene.load(imported_file), sc.Scene.load(OUT / "again.json")
for field in ("mesh_vertices", "mesh_triangles", "cage_vertices", "pose"):
    assert np.array_equal(getattr(first, field), getattr(again, field)), field
assert first.leaf_cages == again.leaf_cages and first.controls == again.controls
print("import then export: the same scene")
bpy.context.view_layer.objects.active = obj

# Coordinates and h per cage: a change binds again (the panel's timer, called here) and the
# stored rig says so.
# The bent leg's cage at the hip (where it bends, another h and coordinates shape the mesh).
limb = name.rsplit(".", 1)[0]
item = next(i for i in obj.starcages_cages if i.name == limb + "_1")
before = evaluated(obj)
item.kind = "GC"
item.own_h = True
item.h = 0.2
ext._rebind_pending()
text = bpy.data.texts[obj["starcages_text"]].as_string()
stored = next(c for c in sc.Scene.load(OUT / "bent.json").leaf_cages if c["name"] == item.name)
rig_now = ext._live_rig(obj)[0]
changed = next(c for c in rig_now.leaf_cages if c["name"] == item.name)
assert changed["kind"] == "gc" and abs(changed["h"] - 0.2) < 1e-6, changed
moved = np.abs(evaluated(obj) - before).max() / diagonal
print(f"cage {item.name}: {stored['kind']} -> gc, h 0.2; the mesh moved {moved:.2e} of the diagonal")
assert moved > 1e-6

# Keyed controls: the rotation keyed at frames 1 and 24; each frame's mesh is the CLI's
# deformation of the scene exported at that frame; a bake plays it back through Mesh Cache
# with its default settings but the frame start the extension sets.
scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 24
control = controls[name]
control.rotation_euler.y = 0.0
control.keyframe_insert("rotation_euler", frame=1)
control.rotation_euler.y = math.radians(60)
control.keyframe_insert("rotation_euler", frame=24)
frames = {}
for frame in (1, 9, 17, 24):
    scene.frame_set(frame)
    frames[frame] = evaluated(obj)
    bpy.ops.starcages.export_scene(filepath=str(OUT / f"frame{frame}.json"))
    expected = cli_deform(OUT / f"frame{frame}.json", OUT / f"frame{frame}.obj")[order][welded_of]
    error = np.abs(frames[frame] - expected).max() / diagonal
    assert error <= 1e-6, (frame, error)
assert np.abs(frames[24] - frames[1]).max() > 1e-2 * diagonal
print("keyed control: frames 1, 9, 17, 24 equal starcages-cli deform of the scene exported there")
bpy.ops.starcages.bake(filepath=str(OUT / "bake.pc2"), remove_rig=True)
assert not obj.get("starcages_text") and obj.data.shape_keys is None
for frame in (1, 9, 17, 24):
    scene.frame_set(frame)
    error = np.abs(evaluated(obj) - frames[frame]).max() / diagonal
    assert error <= 1e-6, (frame, error)
print("bake: Mesh Cache shows frame N at frame N, the rig removed")
obj.modifiers["StarCages bake"].show_viewport = False
assert np.abs(evaluated(obj) - original).max() == 0.0, "the mesh data changed"
print("blender extension: all checks passed")

#!/usr/bin/env python3
"""Blender's Mesh Deform bind time on a StarCages scene's mesh and union cage.

Usage (with Blender 5 as the `bpy` package in a throw-away venv, never a project dependency):
    starcages-cli deform SCENE.json --out /tmp/rest.obj        # the mesh at rest
    starcages-cli cages SCENE.json --out /tmp/cages.obj        # the leaf cages at rest
    VENV/bin/python scripts/blender_mesh_deform_bind.py /tmp/rest.obj /tmp/cages.obj [PRECISION]

The cage given to Mesh Deform is the union of the leaf cages: faces listed by two cages (the
shared faces) are dropped, as StarCages' single-cage baseline does (`--single-cage`). Both
files are read as plain OBJ vertex and face lists into Blender meshes as they are (no axis
conversion, so both stay in the same frame). Prints JSON: vertices, cage faces, precision, the
bind's seconds (the operator plus the evaluation that computes the binding), the seconds of
one re-evaluation after moving one cage vertex, the process's peak resident memory and the part
of it the bind added (MB, Linux).
"""

import json
import resource
import sys
import time

import bpy
from plain_obj import read_obj  # noqa: E402  (beside this script)


def union_faces(faces):
    count = {}
    for f in faces:
        key = tuple(sorted(f))
        count[key] = count.get(key, 0) + 1
    return [f for f in faces if count[tuple(sorted(f))] == 1]


def current_rss_mb():
    """Resident memory of this process now (Linux), in MB."""
    with open("/proc/self/status", encoding="ascii") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return 0.0


def make_object(name, positions, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(positions, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    mesh_path, cage_path = sys.argv[1], sys.argv[2]
    precision = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    bpy.ops.wm.read_factory_settings(use_empty=True)
    positions, faces = read_obj(mesh_path)
    cage_positions, cage_faces = read_obj(cage_path)
    cage_faces = union_faces(cage_faces)
    used = sorted({v for f in cage_faces for v in f})
    renumber = {v: k for k, v in enumerate(used)}
    cage = make_object(
        "cage",
        [cage_positions[v] for v in used],
        [[renumber[v] for v in f] for f in cage_faces],
    )
    target = make_object("mesh", positions, faces)
    modifier = target.modifiers.new("MeshDeform", "MESH_DEFORM")
    modifier.object = cage
    modifier.precision = precision
    bpy.context.view_layer.objects.active = target
    target.select_set(True)
    rss_before_mb = current_rss_mb()
    start = time.perf_counter()
    with bpy.context.temp_override(object=target, active_object=target):
        bpy.ops.object.meshdeform_bind(modifier=modifier.name)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    target.evaluated_get(depsgraph).data.vertices[0].co  # forces the evaluation
    bind_seconds = time.perf_counter() - start
    peak_rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    if not modifier.is_bound:
        sys.exit("Mesh Deform did not bind (is the cage closed around the mesh?)")
    cage.data.vertices[0].co.x += 1e-3
    cage.data.update()
    start = time.perf_counter()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    target.evaluated_get(depsgraph).data.vertices[0].co
    move_seconds = time.perf_counter() - start
    print(
        json.dumps(
            {
                "vertices": len(positions),
                "cage_faces": len(cage_faces),
                "precision": precision,
                "bind_seconds": round(bind_seconds, 4),
                "move_seconds": round(move_seconds, 5),
                "peak_rss_mb": round(peak_rss_mb, 1),
                "bind_rss_mb": round(peak_rss_mb - rss_before_mb, 1),
            }
        )
    )


main()

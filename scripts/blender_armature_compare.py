"""Blender's armature (bone heat: automatic weights, linear blend skinning) on the auto rig's
own joints, beside the auto rig's controls, on the same mesh and the same poses.

Run with a Python that has `bpy` (Blender as a module, from PyPI; a throw-away venv, never a
project dependency) and numpy:

    starcages-cli autorig MESH.obj --out rig.json
    starcages-cli info rig.json --json > rig_info.json
    starcages-cli deform rig.json --apply "leg.L.2: rotate 1 0 0 90" --out ours_knee.obj
    python scripts/blender_armature_compare.py MESH.obj rig_info.json \
        --pose knee "leg.L.2: rotate 1 0 0 90" ours_knee.obj  [--pose NAME EDIT OURS.obj ...]
    # or the issue's poses (hip 45, knee 90, elbow 90, forearm twist 90, neck 30), deformed by
    # the CLI on the left side's controls:
    python scripts/blender_armature_compare.py MESH.obj rig_info.json --cli starcages-cli rig.json

Bones: per limb, one bone per control from its pivot to the next control's pivot (the last one
as long again as the one before it), parented along the limb and to a body bone from the
legs' joints up to the arms' joints (or the mesh's centre line); the mesh is parented with
automatic weights. A pose turns the bone of the named control about its head (the control's
pivot) by the same world rotation. For each pose it prints, for ours and for Blender's: the
volume change of the part that moves (the vertices either result moves by more than 1e-4 of
the diagonal, closed by a fan across its open border), the whole mesh's volume change, the
largest move of the vertices StarCages keeps still (as a share of the diagonal), and for a twist the smallest ratio of a cross-section's size (mean distance from
the bone's axis in slices along it) to its size at rest.

Frames: OBJ files are read as Blender reads them (Y-up, stood up along Z), which is StarCages'
Z-up frame, so `--apply` axes and the pivots of `info --json` are Blender's world axes.
"""

import argparse
import json
import math
import sys

import bpy
import numpy as np
from mathutils import Matrix, Quaternion, Vector


def read_obj(path):
    """Vertices (in the file's axes) and triangles of an OBJ (fans for polygons)."""
    vertices, triangles = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                vertices.append([float(x) for x in w[1:4]])
            elif w[0] == "f":
                idx = [int(x.split("/")[0]) - 1 for x in w[1:]]
                for k in range(1, len(idx) - 1):
                    triangles.append([idx[0], idx[k], idx[k + 1]])
    return np.array(vertices), np.array(triangles, dtype=np.int64)


def z_up(points):
    """A Y-up file's points in the Z-up frame: (x, y, z) -> (x, -z, y)."""
    return np.stack([points[:, 0], -points[:, 2], points[:, 1]], axis=1)


def volume(points, triangles):
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def part_volume(points, triangles, member):
    """Volume of the triangles with every corner in `member`, closed by a fan from the
    centroid of the open border."""
    keep = member[triangles].all(axis=1)
    part = triangles[keep]
    edges = {}
    for t in part:
        for k in range(3):
            a, b = int(t[k]), int(t[(k + 1) % 3])
            key = (min(a, b), max(a, b))
            edges[key] = edges.get(key, 0) + (1 if a < b else -1)
    border = [
        (int(t[k]), int(t[(k + 1) % 3]))
        for t in part
        for k in range(3)
        if edges[(min(t[k], t[(k + 1) % 3]), max(t[k], t[(k + 1) % 3]))] != 0
    ]
    corners = sorted({v for e in border for v in e})
    centre = points[corners].mean(axis=0) if corners else np.zeros(3)
    total = volume(points, part)
    for a, b in border:
        p, q = points[b], points[a]
        total += float(np.dot(p, np.cross(q, centre)) / 6.0)
    return total


def build_armature(controls, mesh_obj):
    """Bones on the controls' pivots (see the module); returns the armature object."""
    by_limb = {}
    for c in controls:
        if c["limb"] is None:
            continue
        by_limb.setdefault(c["limb"], []).append(c)
    for limb in by_limb.values():
        limb.sort(key=lambda c: int(c["name"].rsplit(".", 1)[1]))
    bpy.ops.object.armature_add(enter_editmode=True, location=(0, 0, 0))
    arm = bpy.context.object
    bones = arm.data.edit_bones
    for b in list(bones):
        bones.remove(b)
    lo = Vector(mesh_obj.bound_box[0])
    hi = Vector(mesh_obj.bound_box[6])
    hips = [Vector(l[0]["pivot"]) for name, l in by_limb.items() if name.startswith("leg")]
    shoulders = [Vector(l[0]["pivot"]) for name, l in by_limb.items() if name.startswith("arm")]
    centre = (lo + hi) / 2
    base = sum(hips, Vector()) / len(hips) if hips else Vector((centre.x, centre.y, lo.z))
    top = sum(shoulders, Vector()) / len(shoulders) if shoulders else Vector((centre.x, centre.y, hi.z))
    if (top - base).length < 1e-6:
        top = base + Vector((0, 0, (hi.z - lo.z) * 0.5))
    body = bones.new("body")
    body.head, body.tail = base, top
    made = {}
    for limb, chain in by_limb.items():
        parent = body
        for k, c in enumerate(chain):
            head = Vector(c["pivot"])
            if k + 1 < len(chain):
                tail = Vector(chain[k + 1]["pivot"])
            elif k > 0:
                tail = head + (head - Vector(chain[k - 1]["pivot"]))
            else:
                tail = head + (head - centre).normalized() * 0.1 * (hi - lo).length
            bone = bones.new(c["name"])
            bone.head, bone.tail = head, tail
            bone.parent = parent
            bone.use_connect = False
            parent = bone
            made[c["name"]] = bone
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.select_all(action="DESELECT")
    mesh_obj.select_set(True)
    arm.select_set(True)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    return arm


def parse_edit(text):
    name, op = text.rsplit(":", 1)
    words = op.split()
    assert words[0] == "rotate", "only rotate edits are compared"
    axis = Vector([float(x) for x in words[1:4]]).normalized()
    return name.strip(), axis, math.radians(float(words[4]))


def pose_blender(arm, mesh_obj, edit):
    name, axis, angle = parse_edit(edit)
    for pb in arm.pose.bones:
        pb.rotation_mode = "QUATERNION"
        pb.rotation_quaternion = Quaternion()
    bpy.context.view_layer.update()
    pb = arm.pose.bones[name]
    world = Quaternion(axis, angle).to_matrix()
    rest = pb.bone.matrix_local.to_3x3()
    local = rest.inverted() @ world @ rest
    pb.rotation_quaternion = local.to_quaternion()
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = mesh_obj.evaluated_get(depsgraph)
    return np.array([list(v.co) for v in evaluated.data.vertices]), pb


def twist_ratio(rest, posed, moving, head, tail):
    """Smallest ratio of a slice's mean distance from the axis head–tail (posed: its turned
    image) to the same slice's at rest, over slices along the bone."""
    axis = tail - head
    length = np.linalg.norm(axis)
    axis = axis / length
    t = (rest - head) @ axis
    ratios = []
    for s in np.linspace(0.0, 1.0, 11)[:-1]:
        sel = moving & (t >= s * length) & (t < (s + 0.1) * length)
        if sel.sum() < 8:
            continue
        def size(p):
            c = p[sel].mean(axis=0)
            d = p[sel] - c
            d = d - np.outer(d @ axis, axis)
            return np.linalg.norm(d, axis=1).mean()
        ratios.append(size(posed) / size(rest))
    return min(ratios) if ratios else float("nan")


def standard_poses(controls):
    """The issue's poses on the rig's own controls: hip 45°, knee 90°, elbow 90°, forearm
    twist 90°, neck 30° where those controls exist (the left side's)."""
    by_name = {c["name"]: c for c in controls}
    pivot = lambda n: np.array(by_name[n]["pivot"])
    poses = []
    if "leg.L.1" in by_name:
        poses.append(("hip45", "leg.L.1: rotate 1 0 0 45"))
    if "leg.L.2" in by_name:
        poses.append(("knee90", "leg.L.2: rotate 1 0 0 90"))
    if "arm.L.2" in by_name and "arm.L.3" in by_name:
        forearm = pivot("arm.L.3") - pivot("arm.L.2")
        forearm /= np.linalg.norm(forearm)
        bend = np.cross(forearm, [0.0, 0.0, 1.0])
        bend /= np.linalg.norm(bend)
        poses.append(("elbow90", "arm.L.2: rotate %.6f %.6f %.6f 90" % tuple(bend)))
        poses.append(("twist90", "arm.L.2: rotate %.6f %.6f %.6f 90" % tuple(forearm)))
    for neck in ("neck.1", "head.1"):
        if neck in by_name:
            poses.append(("neck30", f"{neck}: rotate 0 0 1 30"))
            break
    return poses


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mesh")
    parser.add_argument("info")
    parser.add_argument("--pose", nargs=3, action="append", metavar=("NAME", "EDIT", "OURS"))
    parser.add_argument(
        "--cli",
        help="starcages-cli and the rig's scene (SCENE): deform the standard poses with it",
        nargs=2,
        metavar=("CLI", "SCENE"),
    )
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=args.mesh)
    mesh_obj = bpy.context.selected_objects[0]
    # Blender keeps the file's coordinates and stands the object up with its matrix: apply it,
    # so that the mesh's data is in the Z-up frame the pivots are in.
    bpy.context.view_layer.objects.active = mesh_obj
    bpy.ops.object.transform_apply(location=True, rotation=True, scale=True)
    controls = json.load(open(args.info))["controls"]
    poses = list(args.pose or [])
    if args.cli:
        import subprocess
        import tempfile

        cli, scene = args.cli
        out = tempfile.mkdtemp()
        for name, edit in standard_poses(controls):
            path = f"{out}/{name}.obj"
            subprocess.run([cli, "deform", scene, "--apply", edit, "--out", path], check=True,
                           stdout=subprocess.DEVNULL)
            poses.append((name, edit, path))
    rest_file, triangles = read_obj(args.mesh)
    rest = z_up(rest_file)
    blender_rest = np.array([list(v.co) for v in mesh_obj.data.vertices])
    # Blender keeps single precision: compare within 1e-6 of the mesh's size (the beast spans
    # 300 units, where float32 steps are 1.5e-5).
    size = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    if blender_rest.shape != rest.shape or np.abs(blender_rest - rest).max() > 1e-6 * size:
        sys.exit("Blender's vertex order differs from the file's; use a mesh without seams")
    arm = build_armature(controls, mesh_obj)
    diag = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    whole = volume(rest, triangles)
    print(f"mesh: {args.mesh}, {len(rest)} vertices, volume {whole:.6g}")
    for name, edit, ours_path in poses:
        ours = z_up(read_obj(ours_path)[0])
        theirs, pb = pose_blender(arm, mesh_obj, edit)
        def moved(p):
            return np.linalg.norm(p - rest, axis=1) > 1e-4 * diag

        moving = moved(ours) | moved(theirs)
        # What StarCages keeps still (the other limbs and the body): how far Blender moves it.
        kept = ~moved(ours)
        limb = part_volume(rest, triangles, moving)
        head = np.array(pb.bone.head_local)
        tail = np.array(pb.bone.tail_local)
        for who, posed in [("StarCages", ours), ("Blender LBS", theirs)]:
            part = (part_volume(posed, triangles, moving) - limb) / limb
            total = (volume(posed, triangles) - whole) / whole
            others = np.linalg.norm(posed - rest, axis=1)[kept]
            still = others.max() / diag if len(others) else 0.0
            line = (
                f"{name:<8} {who:<12} moving part {100 * part:+6.2f} %  mesh {100 * total:+6.3f} %"
                f"  where StarCages keeps still: up to {100 * still:.3f} % of the diagonal"
            )
            if "twist" in name or "elbow" in name:
                line += f"  smallest cross-section {twist_ratio(rest, posed, moving, head, tail):.3f}"
            print(line)


if __name__ == "__main__":
    main()

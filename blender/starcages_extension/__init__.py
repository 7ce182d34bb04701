"""StarCages for Blender: a *Cages rig on the active mesh, posed live.

StarCages tab in the 3D view's sidebar:

* Auto rig: leaf cages around the active mesh (one wire object, `<mesh>.cages`) and one empty
  per control at its joint, parented from the body out, so Blender's own G/R/S, keyframes,
  the Graph Editor, NLA, drivers and constraints pose and animate them.
* Live deformation: whenever a control moves, a cage vertex is moved in Edit Mode on the cage
  object (a hand move on top of the controls' pose, kept), or the frame changes, the mesh
  follows through a
  shape key named "StarCages" (the mesh's own data stays as it was: Remove rig gives it back).
  The rig (a StarCages scene) is kept in a text block, so it survives saving the .blend.
* Per leaf cage: its coordinates (MVC, HC, GC) and h, and the scene's default h (the rig
  binds again a moment after a change).
* Bake to a PC2 point cache played by a Mesh Cache modifier set to show frame N at frame N
  (the rig removed, for files that must open without the extension), or Apply the current
  shape.
* Import and export of StarCages scene files.

Arrays go to the `starcages` package in the mesh's local coordinates (Z up, as StarCages).
"""

import os
import tempfile

import bpy
import numpy as np
from bpy.app.handlers import persistent
from mathutils import Matrix

import starcages as sc

SHAPE_KEY = "StarCages"
TEXT_PREFIX = "StarCages "

# Per rigged object name: (scene, binding, welded index of each Blender vertex, signature).
_live: dict = {}
_updating = False


def _mesh_arrays(obj):
    """The mesh's vertices (local, rest: the basis shape) and triangles."""
    mesh = obj.data
    n = len(mesh.vertices)
    co = np.empty(n * 3)
    if mesh.shape_keys and mesh.shape_keys.reference_key:
        mesh.shape_keys.reference_key.data.foreach_get("co", co)
    else:
        mesh.vertices.foreach_get("co", co)
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return co.reshape(n, 3), tris.reshape(-1, 3)


def _rig_matrix(obj):
    """Rig space: the object's world matrix when it was rigged (the mesh as it stands in the
    scene, Z up, whatever the object's own rotation): arrays go to StarCages in it."""
    stored = obj.get("starcages_rig_matrix")
    if stored is None:
        return Matrix.Identity(4)
    return Matrix(np.array(stored).reshape(4, 4).tolist())


def _transformed(matrix, points):
    m = np.array(matrix)
    return points @ m[:3, :3].T + m[:3, 3]


def _rig_vertices(obj):
    """The mesh's rest vertices in rig space."""
    vertices, _ = _mesh_arrays(obj)
    return _transformed(_rig_matrix(obj), vertices)


def _welded_of(vertices):
    """Per vertex, its welded vertex as StarCages numbers them (first occurrence first)."""
    first = {}
    out = np.empty(len(vertices), dtype=np.int64)
    for i, p in enumerate(vertices):
        key = tuple(float(c) + 0.0 for c in p)
        out[i] = first.setdefault(key, len(first))
    return out


def _scene_from_text(text):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "rig.json")
        with open(path, "w") as f:
            f.write(text.as_string())
        return sc.Scene.load(path)


def _store_scene(obj, scene):
    name = TEXT_PREFIX + obj.name
    text = bpy.data.texts.get(name) or bpy.data.texts.new(name)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "rig.json")
        scene.save(path)
        with open(path) as f:
            text.from_string(f.read())
    obj["starcages_text"] = name


def _controls_of(obj):
    return [o for o in bpy.data.objects if o.get("starcages_rig") == obj.name and o.type == "EMPTY"]


def _cages_of(obj):
    return next((o for o in bpy.data.objects if o.get("starcages_cages") == obj.name), None)


def _live_rig(obj):
    """The object's scene and binding, bound again after a file was opened."""
    if obj.name in _live:
        return _live[obj.name]
    text = bpy.data.texts.get(obj.get("starcages_text", ""))
    if text is None:
        return None
    scene = _scene_from_text(text)
    entry = [scene, scene.bind(), _welded_of(_rig_vertices(obj)), None]
    _live[obj.name] = entry
    return entry


def _control_transforms(obj):
    """Each control's rest-to-posed transform in rig space (following the object if it moved
    since it was rigged)."""
    to_rig = _rig_matrix(obj) @ obj.matrix_world.inverted()
    transforms = {}
    for empty in _controls_of(obj):
        rest = Matrix(np.array(empty["starcages_rest"]).reshape(4, 4).tolist())
        now = to_rig @ empty.matrix_world
        transforms[empty["starcages_control"]] = np.array(now @ rest.inverted())
    return transforms


def _cage_offsets(obj, cage_obj, count, controls_pose):
    """The hand moves of cage vertices on top of the controls' pose (rig space): read from the
    cage object while it is in Edit Mode (and kept on the mesh object), else as kept."""
    if cage_obj is not None and cage_obj.mode == "EDIT":
        import bmesh

        edit = bmesh.from_edit_mesh(cage_obj.data)
        if len(edit.verts) == count:
            edited = np.array([v.co[:] for v in edit.verts])
            offsets = edited - controls_pose
            obj["starcages_offsets"] = offsets.ravel().tolist()
            return offsets
    stored = obj.get("starcages_offsets")
    if stored is not None and len(stored) == 3 * count:
        return np.array(stored).reshape(count, 3)
    return None


def _posed(obj, rig, cage_obj):
    """The cage positions now (rig space): the controls' pose with every bent joint keeping
    its volume (as the StarCages editor and CLI pose), the hand moves of cage vertices on top
    (propagated down the cage hierarchy)."""
    scene, binding = rig[0], rig[1]
    transforms = _control_transforms(obj)
    by_controls = scene.posed_by_controls(transforms)
    controls_pose = binding.keep_joint_volumes(by_controls)
    offsets = _cage_offsets(obj, cage_obj, len(by_controls), controls_pose)
    if offsets is None or not offsets.any():
        return controls_pose
    return controls_pose + (scene.posed_by_controls(transforms, offsets) - by_controls)


def update_rig(obj, force=False):
    """Deforms `obj` to its controls and the hand moves of its cage vertices (Edit Mode on the
    cage object): the StarCages shape key and the cage object follow."""
    rig = _live_rig(obj)
    if rig is None:
        return
    cage_obj = _cages_of(obj)
    cages = _posed(obj, rig, cage_obj)
    # Leaving Edit Mode on the cage object writes its mesh back: the shape key is written
    # again then too.
    now = (hash(np.round(cages, 12).tobytes()), cage_obj.mode if cage_obj else None)
    if now == rig[3] and not force:
        return
    rig[3] = now
    deformed = _deformed_local(obj, rig, cages)
    key = obj.data.shape_keys.key_blocks.get(SHAPE_KEY) if obj.data.shape_keys else None
    if key is None:
        if obj.data.shape_keys is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        key = obj.shape_key_add(name=SHAPE_KEY, from_mix=False)
        key.value = 1.0
    key.data.foreach_set("co", deformed.ravel())
    if cage_obj is not None and cage_obj.mode != "EDIT":
        cage_obj.data.vertices.foreach_set("co", cages.ravel())
        cage_obj.data.update()
    obj.data.update()


def _posed_cages(obj, rig):
    """The cage positions now: the controls' pose and the hand moves on top."""
    return _posed(obj, rig, _cages_of(obj))


def _deformed_local(obj, rig, cages):
    """The mesh (per Blender vertex, the object's local coordinates) for cage positions."""
    scene, binding, welded_of, _ = rig
    return _transformed(_rig_matrix(obj).inverted(), binding.deform(cages)[welded_of])


@persistent
def _on_update(scene_, depsgraph=None):
    global _updating
    if _updating:
        return
    _updating = True
    try:
        for obj in list(bpy.data.objects):
            if obj.type == "MESH" and obj.get("starcages_text"):
                update_rig(obj)
    finally:
        _updating = False


@persistent
def _on_load(_):
    # The rigs are bound again from their text blocks; the objects' matrices are evaluated
    # first (at load they may not be yet).
    _live.clear()
    for view_layer in (v for s in bpy.data.scenes for v in s.view_layers):
        view_layer.update()
    _on_update(None)


def _fill_cage_settings(obj, scene):
    """The panel's per-cage rows and the default h, from the scene (no rebind)."""
    global _filling
    _filling = True
    try:
        obj.starcages_cages.clear()
        for cage in scene.leaf_cages:
            item = obj.starcages_cages.add()
            item.name = cage["name"]
            item.kind = cage["kind"].upper()
            item.own_h = cage["h"] is not None
            item.h = cage["h"] if cage["h"] is not None else scene.default_h
        obj.starcages_default_h = scene.default_h
    finally:
        _filling = False


_filling = False
_pending_rebind: set = set()


def _rebind_pending():
    """Applies the panel's coordinates and h to the rigs whose rows changed, binds again."""
    for name in list(_pending_rebind):
        _pending_rebind.discard(name)
        obj = bpy.data.objects.get(name)
        rig = obj and _live_rig(obj)
        if not rig:
            continue
        scene = rig[0]
        try:
            scene = scene.with_default_h(obj.starcages_default_h)
            for item in obj.starcages_cages:
                scene = scene.with_cage(
                    item.name,
                    kind=item.kind.lower(),
                    h=item.h if item.own_h else None,
                    scene_h=not item.own_h,
                )
        except sc.StarCagesError as e:
            print("StarCages:", e)
            _fill_cage_settings(obj, rig[0])
            continue
        _store_scene(obj, scene)
        rig[0], rig[1], rig[3] = scene, scene.bind(), None
        update_rig(obj, force=True)
    return None


def _settings_changed(self, context):
    """A row or the default h changed: bind again shortly (a slider drag binds once)."""
    if _filling:
        return
    obj = self.id_data
    _pending_rebind.add(obj.name)
    if not bpy.app.timers.is_registered(_rebind_pending):
        bpy.app.timers.register(_rebind_pending, first_interval=0.3)


class StarCagesCage(bpy.types.PropertyGroup):
    kind: bpy.props.EnumProperty(
        name="Coordinates",
        items=[("MVC", "MVC", "Mean value"), ("HC", "HC", "Harmonic"), ("GC", "GC", "Green")],
        update=_settings_changed,
    )
    own_h: bpy.props.BoolProperty(name="Own h", update=_settings_changed)
    h: bpy.props.FloatProperty(name="h", min=0.0, max=1.0, default=0.5, update=_settings_changed)


def rig_object(obj, scene):
    """Makes `obj` a StarCages rig of `scene` (its mesh's welded vertices must be obj's)."""
    _store_scene(obj, scene)
    _fill_cage_settings(obj, scene)
    cages = scene.cage_vertices
    faces = []
    seen = set()
    for cage in scene.leaf_cages:
        for face in cage["faces"]:
            key = tuple(sorted(face))
            if key not in seen:
                seen.add(key)
                faces.append(face)
    mesh = bpy.data.meshes.new(obj.name + ".cages")
    mesh.from_pydata(cages.tolist(), [], faces)
    cage_obj = bpy.data.objects.new(obj.name + ".cages", mesh)
    cage_obj.display_type = "WIRE"
    cage_obj.hide_render = True
    cage_obj.matrix_world = obj.matrix_world @ _rig_matrix(obj).inverted()
    cage_obj["starcages_cages"] = obj.name
    collection = obj.users_collection[0] if obj.users_collection else bpy.context.scene.collection
    collection.objects.link(cage_obj)
    parents = scene.control_parents()
    empties = {}
    size = float(np.linalg.norm(cages.max(axis=0) - cages.min(axis=0))) * 0.04
    for control in scene.controls:
        corners = sorted({v for face in control["faces"] for v in face})
        pivot = control["pivot"] if control["pivot"] is not None else cages[corners].mean(axis=0)
        empty = bpy.data.objects.new(f"{obj.name}.{control['name']}", None)
        empty.empty_display_type = "SPHERE"
        empty.empty_display_size = size
        empty.matrix_world = obj.matrix_world @ _rig_matrix(obj).inverted() @ Matrix.Translation(pivot)
        empty["starcages_rig"] = obj.name
        empty["starcages_control"] = control["name"]
        collection.objects.link(empty)
        empties[control["name"]] = empty
    # Parented body out, keeping each where it is.
    for name, parent in parents.items():
        if parent is not None:
            child = empties[name]
            world = child.matrix_world.copy()
            child.parent = empties[parent]
            child.matrix_parent_inverse = empties[parent].matrix_world.inverted()
            child.matrix_world = world
    to_rig = _rig_matrix(obj) @ obj.matrix_world.inverted()
    for empty in empties.values():
        rest = to_rig @ empty.matrix_world
        empty["starcages_rest"] = [v for row in rest for v in row]
    _live.pop(obj.name, None)
    update_rig(obj, force=True)


def remove_rig(obj):
    """Removes the rig: the shape key, cage object, controls and text go; the mesh is as it was."""
    keys = obj.data.shape_keys
    if keys and keys.key_blocks.get(SHAPE_KEY):
        obj.shape_key_remove(keys.key_blocks[SHAPE_KEY])
        if len(obj.data.shape_keys.key_blocks) == 1:
            obj.shape_key_remove(obj.data.shape_keys.key_blocks[0])
    for o in _controls_of(obj) + [c for c in [_cages_of(obj)] if c]:
        bpy.data.objects.remove(o)
    text = bpy.data.texts.get(obj.get("starcages_text", ""))
    if text:
        bpy.data.texts.remove(text)
    for prop in ("starcages_text", "starcages_rig_matrix", "starcages_offsets"):
        if prop in obj:
            del obj[prop]
    _live.pop(obj.name, None)


class _OnRig:
    """Operators on a rigged active object."""

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and bool(obj.get("starcages_text"))


class STARCAGES_OT_autorig(bpy.types.Operator):
    """Auto rig the active mesh: leaf cages along its limbs and a control per segment"""

    bl_idname = "starcages.autorig"
    bl_label = "Auto rig"
    bl_options = {"REGISTER", "UNDO"}

    detail: bpy.props.IntProperty(name="Detail", default=3, min=1, max=5)
    mirror: bpy.props.EnumProperty(
        name="Mirror",
        items=[("NONE", "None", ""), ("auto", "Auto", ""), ("x", "X", ""), ("y", "Y", ""), ("z", "Z", "")],
        default="NONE",
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and not obj.get("starcages_text")

    def execute(self, context):
        obj = context.active_object
        # Rig space: the mesh as it stands in the scene (an importer's rotation included).
        obj["starcages_rig_matrix"] = [v for row in obj.matrix_world for v in row]
        vertices = _rig_vertices(obj)
        _, triangles = _mesh_arrays(obj)
        try:
            scene = sc.autorig(
                vertices,
                triangles,
                detail=self.detail,
                mirror=None if self.mirror == "NONE" else self.mirror,
                up="z",
            )
        except sc.StarCagesError as e:
            del obj["starcages_rig_matrix"]
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        rig_object(obj, scene)
        self.report({"INFO"}, f"{len(scene.leaf_cages)} cages, {len(scene.controls)} controls")
        return {"FINISHED"}


class STARCAGES_OT_remove(_OnRig, bpy.types.Operator):
    """Remove the StarCages rig: the mesh is as it was before"""

    bl_idname = "starcages.remove"
    bl_label = "Remove rig"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        remove_rig(context.active_object)
        return {"FINISHED"}


def write_pc2(path, samples, start_frame):
    """A PC2 point cache of `samples` (frames × points × 3), starting at `start_frame`."""
    samples = np.asarray(samples, dtype="<f4")
    header = b"POINTCACHE2\0" + np.array([1, samples.shape[1]], dtype="<i4").tobytes()
    header += np.array([start_frame, 1.0], dtype="<f4").tobytes()
    header += np.array([samples.shape[0]], dtype="<i4").tobytes()
    tmp = path + ".part"
    with open(tmp, "wb") as f:
        f.write(header)
        f.write(samples.tobytes())
    os.replace(tmp, path)


class STARCAGES_OT_bake(_OnRig, bpy.types.Operator):
    """Bake the rig's animation (the scene's frame range) into a PC2 point cache and play it
    through a Mesh Cache modifier set to show frame N at frame N; optionally remove the rig,
    so the file opens without the extension"""

    bl_idname = "starcages.bake"
    bl_label = "Bake to point cache"
    bl_options = {"REGISTER", "UNDO"}
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    remove_rig: bpy.props.BoolProperty(name="Remove rig", default=True)

    def invoke(self, context, event):
        self.filepath = bpy.path.ensure_ext(bpy.path.abspath("//" + context.active_object.name), ".pc2")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = context.active_object
        scene = context.scene
        keep = scene.frame_current
        rig = _live_rig(obj)
        samples = []
        for frame in range(scene.frame_start, scene.frame_end + 1):
            scene.frame_set(frame)
            update_rig(obj)
            samples.append(_deformed_local(obj, rig, _posed_cages(obj, rig)))
        scene.frame_set(keep)
        path = bpy.path.abspath(self.filepath)
        write_pc2(path, samples, float(scene.frame_start))
        if self.remove_rig:
            remove_rig(obj)
        cache = obj.modifiers.new("StarCages bake", "MESH_CACHE")
        cache.cache_format = "PC2"
        cache.filepath = path
        # The modifier ignores the file's start frame: frame N shows sample N - frame_start.
        cache.frame_start = float(scene.frame_start)
        self.report({"INFO"}, f"{len(samples)} frames baked to {path}")
        return {"FINISHED"}


class STARCAGES_OT_apply(_OnRig, bpy.types.Operator):
    """Apply the rig: the mesh keeps its current deformed shape and the rig goes"""

    bl_idname = "starcages.apply"
    bl_label = "Apply rig"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        obj = context.active_object
        rig = _live_rig(obj)
        deformed = _deformed_local(obj, rig, _posed_cages(obj, rig))
        remove_rig(obj)
        obj.data.vertices.foreach_set("co", deformed.ravel())
        obj.data.update()
        return {"FINISHED"}


class STARCAGES_OT_export(_OnRig, bpy.types.Operator):
    """Export the rig, in its current pose, as a StarCages scene file"""

    bl_idname = "starcages.export_scene"
    bl_label = "Export StarCages scene"
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = context.active_object
        rig = _live_rig(obj)
        rig[0].with_pose(_posed_cages(obj, rig)).save(bpy.path.abspath(self.filepath))
        return {"FINISHED"}


class STARCAGES_OT_import(bpy.types.Operator):
    """Import a StarCages scene file: its mesh, rigged"""

    bl_idname = "starcages.import_scene"
    bl_label = "Import StarCages scene"
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            scene = sc.Scene.load(bpy.path.abspath(self.filepath))
        except sc.StarCagesError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        # Blender is Z-up: a Y-up scene's arrays are turned to Z-up.
        vertices = scene.to_scene_axes(scene.mesh_vertices) if scene.up == "y" else scene.mesh_vertices
        name = os.path.splitext(os.path.basename(self.filepath))[0]
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata(vertices.tolist(), [], scene.mesh_triangles.tolist())
        obj = bpy.data.objects.new(name, mesh)
        context.collection.objects.link(obj)
        if scene.up == "y":
            self.report({"WARNING"}, "a Y-up scene: its rig is rebuilt Z-up by Auto rig")
            return {"FINISHED"}
        rig_object(obj, scene)
        return {"FINISHED"}


class STARCAGES_PT_panel(bpy.types.Panel):
    bl_label = "StarCages"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "StarCages"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        layout.operator(STARCAGES_OT_autorig.bl_idname)
        layout.operator(STARCAGES_OT_remove.bl_idname)
        layout.operator(STARCAGES_OT_import.bl_idname)
        layout.operator(STARCAGES_OT_export.bl_idname)
        if obj is not None and obj.get("starcages_text"):
            rig = _live_rig(obj)
            if rig:
                scene = rig[0]
                layout.label(text=f"{len(scene.leaf_cages)} cages, {len(scene.controls)} controls")
            layout.operator(STARCAGES_OT_bake.bl_idname)
            layout.operator(STARCAGES_OT_apply.bl_idname)
            layout.prop(obj, "starcages_default_h", text="Default h")
            box = layout.box()
            for item in obj.starcages_cages:
                row = box.row(align=True)
                row.label(text=item.name)
                row.prop(item, "kind", text="")
                row.prop(item, "own_h", text="")
                sub = row.row(align=True)
                sub.enabled = item.own_h
                sub.prop(item, "h", text="h")


CLASSES = (
    StarCagesCage,
    STARCAGES_OT_bake,
    STARCAGES_OT_apply,
    STARCAGES_OT_autorig,
    STARCAGES_OT_remove,
    STARCAGES_OT_export,
    STARCAGES_OT_import,
    STARCAGES_PT_panel,
)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.starcages_cages = bpy.props.CollectionProperty(type=StarCagesCage)
    bpy.types.Object.starcages_default_h = bpy.props.FloatProperty(
        name="Default h", min=0.0, max=1.0, default=0.5, update=_settings_changed
    )
    bpy.app.handlers.depsgraph_update_post.append(_on_update)
    bpy.app.handlers.frame_change_post.append(_on_update)
    bpy.app.handlers.load_post.append(_on_load)


def unregister():
    for handlers, fn in (
        (bpy.app.handlers.depsgraph_update_post, _on_update),
        (bpy.app.handlers.frame_change_post, _on_update),
        (bpy.app.handlers.load_post, _on_load),
    ):
        if fn in handlers:
            handlers.remove(fn)
    del bpy.types.Object.starcages_cages
    del bpy.types.Object.starcages_default_h
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)

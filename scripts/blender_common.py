"""What the headless Blender scripts share: the extension loaded from this checkout (its
folder is not named after the `starcages` package it imports, so it is loaded by path and
registered), a mesh file imported as Blender's OBJ importer does (Y up to Z up), and frames
rendered with the rig hidden."""

import importlib.util
from pathlib import Path

import bpy

ROOT = Path(__file__).resolve().parents[1]


def load_extension():
    """The extension module, registered."""
    spec = importlib.util.spec_from_file_location(
        "starcages_extension", ROOT / "blender" / "starcages_extension" / "__init__.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.register()
    return module


def import_mesh(path):
    """An empty scene with the OBJ at `path` imported, its object active."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=str(path), forward_axis="NEGATIVE_Z", up_axis="Y")
    obj = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
    bpy.context.view_layer.objects.active = obj
    return obj


def render_frames(scene, out, name, frames, resolution):
    """Renders `frames` of `scene` with Workbench to OUT/NAME_frameN.png, the rig's cage and
    control objects hidden."""
    for o in bpy.data.objects:
        if o.get("starcages_cages") or o.get("starcages_rig"):
            o.hide_render = True
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    for frame in frames:
        scene.frame_set(frame)
        scene.render.filepath = str(out / f"{name}_frame{frame}.png")
        bpy.ops.render.render(write_still=True)

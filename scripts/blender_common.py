"""What the headless Blender scripts share: the extension loaded from this checkout (its
folder is not named after the `starcages` package it imports, so it is loaded by path and
registered), and a mesh file imported as Blender's OBJ importer does (Y up to Z up)."""

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

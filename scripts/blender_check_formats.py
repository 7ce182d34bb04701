"""Checks StarCages' PLY and STL readers against Blender's exporters.

Blender imports MESH.obj (Y-up), exports it as binary and ASCII PLY and STL (Z-up, Blender's
default), and `starcages-cli autocage FILE --up z` reads each; every file must give the same
welded vertex count, triangle count and bounds as the OBJ read Y-up.

Blender is not a project dependency: install it in a throw-away virtual environment outside
the project (`python3.11 -m venv /tmp/bpy && /tmp/bpy/bin/pip install bpy`), then

    /tmp/bpy/bin/python scripts/blender_check_formats.py MESH.obj OUT_DIR [--cli PATH]

It prints one line per file and exits with status 1 when one differs.
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--cli", default="target/release/starcages-cli")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=str(args.mesh))
    exports = {
        "binary.ply": lambda p: bpy.ops.wm.ply_export(filepath=p, ascii_format=False),
        "ascii.ply": lambda p: bpy.ops.wm.ply_export(filepath=p, ascii_format=True),
        "binary.stl": lambda p: bpy.ops.wm.stl_export(filepath=p, ascii_format=False),
        "ascii.stl": lambda p: bpy.ops.wm.stl_export(filepath=p, ascii_format=True),
    }
    for name, export in exports.items():
        export(str(args.out / name))

    def summary(mesh, up):
        scene = args.out / (mesh.name + ".json")
        subprocess.run([args.cli, "autocage", str(mesh), "--grid", "1", "1", "1",
                        "--up", up, "--out", str(scene)], check=True, capture_output=True)
        info = json.loads(subprocess.run([args.cli, "info", str(scene), "--json"], check=True,
                                         capture_output=True).stdout)["mesh"]
        return info

    reference = summary(args.mesh, "y")
    diagonal = sum((a - b) ** 2 for a, b in
                   zip(reference["bounds_max"], reference["bounds_min"])) ** 0.5
    failures = 0
    for name in exports:
        info = summary(args.out / name, "z")
        off = max(abs(a - b) for key in ["bounds_min", "bounds_max"]
                  for a, b in zip(info[key], reference[key]))
        same = (info["welded_vertices"] == reference["welded_vertices"]
                and info["triangles"] == reference["triangles"] and off <= 1e-6 * diagonal)
        failures += not same
        print(f"{name}: {info['vertices']} vertices ({info['welded_vertices']} welded), "
              f"{info['triangles']} triangles, bounds off by {off:.3g} "
              f"{'ok' if same else 'DIFFERENT'}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

"""Exports a textured mesh from Blender (the `bpy` package, headless) as the artists' files
StarCages reads materials from: a GLB with the image embedded, a glTF with the image beside it,
and an FBX with the image embedded. The mesh is imported from an OBJ with UVs (e.g.
../shared/meshes/spot.obj), given a material whose base colour is Blender's generated colour
grid image (so the image's orientation shows), and exported.

    /tmp/bpyvenv/bin/python scripts/blender_textured_export.py MESH.obj OUT_FOLDER

Then `starcages-cli autocage OUT_FOLDER/NAME.glb --out s.json` and
`starcages-cli render s.json --shading textured --png t.png` (or open the file in the
editor, View panel, Shading: Textured) show whether the material came through; Blender's own
render of the same file is written as OUT_FOLDER/NAME_blender.png for comparison.
"""

import os
import sys

import bpy


def main() -> None:
    source, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    name = os.path.splitext(os.path.basename(source))[0]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=source, forward_axis="NEGATIVE_Z", up_axis="Y")
    obj = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
    image = bpy.data.images.new("grid", width=512, height=512)
    image.generated_type = "COLOR_GRID"
    image.filepath_raw = os.path.join(out, "grid.png")
    image.file_format = "PNG"
    image.save()
    material = bpy.data.materials.new("grid")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    bsdf = nodes.get("Principled BSDF")
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    obj.data.materials.clear()
    obj.data.materials.append(material)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.export_scene.gltf(
        filepath=os.path.join(out, f"{name}.glb"), export_format="GLB", use_selection=True
    )
    bpy.ops.export_scene.gltf(
        filepath=os.path.join(out, f"{name}.gltf"),
        export_format="GLTF_SEPARATE",
        use_selection=True,
    )
    bpy.ops.export_scene.fbx(
        filepath=os.path.join(out, f"{name}.fbx"),
        use_selection=True,
        path_mode="COPY",
        embed_textures=True,
    )
    # Blender's own look at it (Workbench, texture colour), for comparison.
    scene = bpy.context.scene
    camera_data = bpy.data.cameras.new("camera")
    camera = bpy.data.objects.new("camera", camera_data)
    scene.collection.objects.link(camera)
    scene.camera = camera
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.ops.view3d.camera_to_view_selected() if bpy.context.area else None
    lo = [min(v.co[i] for v in obj.data.vertices) for i in range(3)]
    hi = [max(v.co[i] for v in obj.data.vertices) for i in range(3)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    size = max(b - a for a, b in zip(lo, hi))
    camera.location = (centre[0] + 1.6 * size, centre[1] - 1.6 * size, centre[2] + 1.0 * size)
    direction = camera.location.copy()
    for i in range(3):
        direction[i] = centre[i] - camera.location[i]
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.color_type = "TEXTURE"
    scene.render.resolution_x, scene.render.resolution_y = 480, 360
    scene.render.filepath = os.path.join(out, f"{name}_blender.png")
    bpy.ops.render.render(write_still=True)
    print("wrote", out)


if __name__ == "__main__":
    main()

"""Renders docs/blender.png with the Blender add-on, without a window (Workbench):

    blender -b --factory-startup --python scripts/blender_screenshot.py -- [--sdm-py DIR] [--out PNG]

Left: Spot with the STM layout's checker through its uv layer "STM" (sdm.layout). Right: Spot
encoded as an SDM, decoded at level 2 (sdm.encode, sdm.decode) and given Spot's texture by
sdm.transfer. Between them the skeleton (sdm.skeleton, as a curve).
"""
import argparse
import math
import os
import sys
import tempfile
import traceback

import addon_utils
import bpy
from mathutils import Vector

sys.dont_write_bytecode = True
REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def look_at(obj, target):
    obj.rotation_euler = (Vector(target) - obj.location).to_track_quat('-Z', 'Y').to_euler()


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender_screenshot.py")
    p.add_argument("--sdm-py", default="", help="folder holding sdm_py (default: the add-on's preference default)")
    p.add_argument("--out", default=os.path.join(REPO, "docs", "blender.png"))
    p.add_argument("--width", type=int, default=960)
    p.add_argument("--height", type=int, default=400)
    args = p.parse_args(argv)
    sys.path.insert(0, os.path.join(REPO, "blender"))
    addon_utils.enable("sdm_blender", default_set=True, handle_error=None)
    if args.sdm_py:
        bpy.context.preferences.addons["sdm_blender"].preferences.sdm_py_folder = args.sdm_py
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.wm.obj_import(filepath=os.path.join(REPO, "examples", "data", "spot", "spot_triangulated.obj"))
    spot = bpy.context.active_object

    with tempfile.TemporaryDirectory() as folder:
        exr = os.path.join(folder, "spot.exr")
        bpy.ops.sdm.encode(filepath=exr, size=1024)
        bpy.ops.sdm.decode(filepath=exr, level=2)
    decoded = bpy.context.active_object
    spot.select_set(True)
    bpy.ops.sdm.transfer(size=1024)  # Spot's own texture: the layout gives Spot its checker only below
    bpy.context.view_layer.objects.active = spot
    bpy.ops.sdm.skeleton(output='CURVE')
    skeleton = bpy.data.objects[spot.name + ".skeleton"]
    bpy.ops.sdm.layout(size=1024)

    spot.location.x, decoded.location.x, skeleton.location.x = -1.15, 1.15, 0.0
    skeleton.data.bevel_depth = 0.012
    for o in (spot, decoded, skeleton):
        o.rotation_euler.z = math.radians(215)

    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("camera")
    cam_data.lens = 50
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (0.0, -7.0, 1.9)
    look_at(cam, (0.0, 0.0, 0.1))
    scene.camera = cam
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.display.shading.light = 'STUDIO'
    scene.display.shading.color_type = 'TEXTURE'
    scene.display.shading.show_cavity = False
    scene.render.resolution_x, scene.render.resolution_y = args.width, args.height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = 'Standard'
    scene.world = scene.world or bpy.data.worlds.new("world")
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGB'
    scene.render.image_settings.compression = 100
    scene.render.filepath = args.out
    bpy.ops.render.render(write_still=True)
    print(f"wrote {args.out} ({os.path.getsize(args.out) // 1024} KB)")


if __name__ == "__main__":
    try:
        main()
    except Exception:
        traceback.print_exc()
        sys.exit(1)

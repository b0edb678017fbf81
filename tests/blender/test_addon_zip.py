"""The add-on as a user installs it (run by CTest as blender.addon_zip):

    blender -b --factory-startup --python tests/blender/test_addon_zip.py -- --zip ZIP --sdm-py DIR

with BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG set to empty temporary folders (the wrapper
run_test_addon.sh does so): the zip of scripts/blender_addon_zip.sh installs through
Preferences > Add-ons > Install (bpy.ops.preferences.addon_install), enables, finds no sdm_py
by itself outside the repository (the error says how to set the folder), and with the
preference set lays out a mesh: the uv layer "STM" on every loop, the coverage sdm_py reports.
"""
import argparse
import importlib.util
import os
import sys
import traceback

import addon_utils
import bpy
import numpy as np

sys.dont_write_bytecode = True


def check(condition, what):
    print(("ok    " if condition else "FAIL  ") + what, flush=True)
    if not condition:
        raise AssertionError(what)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="test_addon_zip.py")
    p.add_argument("--zip", required=True)
    p.add_argument("--sdm-py", required=True)
    args = p.parse_args(argv)
    scripts = os.environ.get("BLENDER_USER_SCRIPTS", "")
    check(bool(scripts) and os.environ.get("BLENDER_USER_CONFIG"),
          f"BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG set (to temporary folders: {scripts})")
    check(bpy.ops.preferences.addon_install(filepath=os.path.abspath(args.zip)) == {'FINISHED'},
          f"Preferences > Add-ons > Install of {os.path.basename(args.zip)}")
    installed = os.path.join(bpy.utils.user_resource('SCRIPTS', path="addons"), "sdm_blender", "__init__.py")
    check(os.path.isfile(installed), f"installed as {installed}")
    mod = addon_utils.enable("sdm_blender", default_set=True, handle_error=None)
    check(mod is not None and os.path.realpath(mod.__file__) == os.path.realpath(installed), "enabled from there")
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)
    sphere = bpy.context.active_object
    if importlib.util.find_spec("sdm_py") is None:  # not on Blender's own sys.path
        try:
            bpy.ops.sdm.layout()
            check(False, "without the preference, sdm_py is not found")
        except RuntimeError as e:
            check("Preferences > Add-ons > SDM" in str(e), f"without the preference: {str(e)[:100]}...")
    prefs = bpy.context.preferences.addons["sdm_blender"].preferences
    prefs.sdm_py_folder = args.sdm_py
    check(bpy.ops.sdm.layout(size=512, checker=False) == {'FINISHED'}, "with the preference set, sdm.layout finished")
    import sdm_py
    mesh = sphere.data
    V = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    F = np.array([list(p.vertices) for p in mesh.polygons], dtype=np.int32)
    ref = sdm_py.layout(V, F, size=512)
    check(len(F) == len(mesh.polygons) and all(len(p.vertices) == 3 for p in mesh.polygons),
          f"the sphere's quads triangulated: {len(F)} triangles")
    check("STM" in mesh.uv_layers and len(mesh.uv_layers["STM"].data) == len(mesh.loops),
          f"uv layer 'STM' on its {len(mesh.loops)} loops")
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    mesh.uv_layers["STM"].data.foreach_get("uv", uv)
    uv = uv.reshape(-1, 2)
    err = 0.0
    for t, poly in enumerate(mesh.polygons):
        for c, loop in enumerate(poly.loop_indices):
            j = int(np.flatnonzero(ref["faces"][t] == F[t, c])[0])
            err = max(err, float(np.abs(uv[loop] - ref["uv"][t, j]).max()))
    check(err < 1e-6, f"its uv on every loop is sdm_py.layout's for the triangulated mesh (max difference {err:.1e})")
    check(abs(mesh["sdm_stm_coverage"] - ref["coverage"]) < 1e-9,
          f"coverage {mesh['sdm_stm_coverage']:.6f} = sdm_py.layout's {ref['coverage']:.6f}")
    print("the zip installs and works")


if __name__ == "__main__":
    try:
        main()
    except Exception:  # Blender exits 0 after an uncaught exception: make the failure the exit code
        traceback.print_exc()
        sys.exit(1)

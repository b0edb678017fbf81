"""SDM for Blender: skeleton, STM layout, skeleton displacement maps (decoded per segment at its own
level of detail, posed through the map by an armature) and texture transfer of the active mesh,
through the Python module sdm_py of this repository (no algorithm is re-implemented here)."""

bl_info = {
    "name": "SDM: skeleton texture and displacement maps",
    "author": "sdm",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > SDM; Object > SDM",
    "description": "Curve skeleton, skeleton texture map (STM uv), SDM encode/decode/pose and texture transfer via sdm_py",
    "category": "Mesh",
}

import bpy  # noqa: E402

from . import loader, operators, ui  # noqa: E402

classes = (loader.SdmPreferences,) + operators.classes + ui.classes


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.VIEW3D_MT_object.append(ui.menu_entry)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(ui.menu_entry)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

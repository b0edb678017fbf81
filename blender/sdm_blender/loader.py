"""Where sdm_py comes from: the add-on preference "sdm_py folder", by default the build/python
folder of the repository the add-on lives in (when it runs from a checkout or a symlink into one),
else Blender's sys.path."""
import importlib
import os
import sys

import bpy

ADDON = __package__


def repository_module_folder():
    """build/python beside the add-on's repository (blender/sdm_blender/ -> ../../build/python),
    or "" when the add-on is not inside a built checkout (installed from the zip)."""
    here = os.path.dirname(os.path.realpath(__file__))
    folder = os.path.normpath(os.path.join(here, "..", "..", "build", "python"))
    return folder if os.path.isdir(folder) else ""


class SdmPyMissing(Exception):
    """sdm_py cannot be imported; the message says from where it was looked for and what to do."""


def preferences(context=None):
    context = context or bpy.context
    addon = context.preferences.addons.get(ADDON)
    return addon.preferences if addon else None


def configured_folder(context=None):
    prefs = preferences(context)
    folder = prefs.sdm_py_folder if prefs else ""
    return bpy.path.abspath(folder) if folder else repository_module_folder()


def load(context=None):
    """Imports sdm_py from the configured folder (or sys.path) and returns the module."""
    folder = configured_folder(context)
    fix = ("set Preferences > Add-ons > SDM > 'sdm_py folder' to the build/python folder of an sdm build "
           "(cmake --build build --target sdm_py)")
    if folder:
        if not os.path.isdir(folder):
            raise SdmPyMissing(f"the sdm_py folder {folder!r} does not exist: {fix}, or clear it to use sys.path")
        loaded = sys.modules.get("sdm_py")
        if loaded is not None:
            there = os.path.realpath(os.path.dirname(loaded.__file__))
            if there != os.path.realpath(folder):
                raise SdmPyMissing(f"sdm_py is already loaded from {there!r}, not from {folder!r}: "
                                   "restart Blender for the new folder to take effect")
            return loaded
        if folder not in sys.path:
            sys.path.insert(0, folder)
    try:
        return importlib.import_module("sdm_py")
    except ImportError as e:
        where = repr(folder) if folder else "sys.path"
        tag = f"cpython-{sys.version_info.major}{sys.version_info.minor}"
        raise SdmPyMissing(f"sdm_py could not be imported from {where} ({e}): it must be built for Blender's "
                           f"Python {sys.version_info.major}.{sys.version_info.minor} (a file sdm_py.{tag}-*.so); "
                           f"{fix}") from e


def describe(context=None):
    """One line for the preferences: where sdm_py was found and its version, or why not."""
    try:
        m = load(context)
        return 'INFO', f"sdm_py {getattr(m, '__version__', '?')} from {m.__file__}"
    except SdmPyMissing as e:
        return 'ERROR', str(e)


class SdmPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON

    sdm_py_folder: bpy.props.StringProperty(
        name="sdm_py folder",
        description="Folder holding the sdm_py module (build/python of an sdm build); "
                    "empty: the build/python folder beside the add-on's repository if there is one, else sys.path",
        subtype='DIR_PATH',
        default="",
    )

    def draw(self, context):
        col = self.layout.column()
        col.prop(self, "sdm_py_folder")
        default = repository_module_folder()
        col.label(text=f"Empty means: {default}" if default else "Empty means: Blender's sys.path")
        kind, line = describe(context)
        col.label(text=line, icon='CHECKMARK' if kind == 'INFO' else 'ERROR')

"""The add-on's panel (3D Viewport > Sidebar > SDM) and its menu (Object > SDM)."""
import bpy

from . import loader


class VIEW3D_PT_sdm(bpy.types.Panel):
    bl_label = "SDM"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "SDM"

    def draw(self, context):
        col = self.layout.column(align=True)
        col.operator("sdm.skeleton", icon='ARMATURE_DATA')
        col.operator("sdm.layout", icon='UV')
        col.separator()
        col.operator("sdm.encode", icon='EXPORT')
        col.operator("sdm.decode", icon='IMPORT')
        col.operator("sdm.pose", icon='POSE_HLT')
        col.separator()
        col.operator("sdm.transfer", icon='TEXTURE')
        obj = context.active_object
        if obj is not None and obj.type == 'MESH' and "sdm_stm_coverage" in obj.data:
            box = self.layout.box()
            box.label(text=f"STM coverage {obj.data['sdm_stm_coverage']:.4f}")
            box.label(text=f"L2 stretch {obj.data['sdm_stm_stretch']:.3f}, {obj.data['sdm_stm_segments']} segments")
        kind, line = loader.describe(context)
        if kind == 'ERROR':
            self.layout.label(text="sdm_py not found: see the add-on's preferences", icon='ERROR')


class VIEW3D_MT_sdm(bpy.types.Menu):
    bl_label = "SDM"

    def draw(self, context):
        for op in ("sdm.skeleton", "sdm.layout", "sdm.encode", "sdm.decode", "sdm.pose", "sdm.transfer"):
            self.layout.operator(op)


def menu_entry(self, context):
    self.layout.menu("VIEW3D_MT_sdm")


classes = (VIEW3D_PT_sdm, VIEW3D_MT_sdm)

"""The add-on's operators: each reads the active mesh into arrays, calls sdm_py and turns the
result into Blender data. Nothing is computed here that sdm_py computes; a failure (sdm_py's
ValueError names the problem and its fix) is reported as an error and changes nothing."""
import os
import time

import bmesh
import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty

from . import armature, arrays, images, loader


class Progress:
    """The window manager's progress indicator and a status bar line while an operator runs."""

    def __init__(self, context, title, steps):
        self.wm, self.workspace, self.title, self.k = context.window_manager, context.workspace, title, 0
        self.wm.progress_begin(0, steps)

    def step(self, text):
        self.wm.progress_update(self.k)
        self.k += 1
        if self.workspace is not None:
            self.workspace.status_text_set(f"SDM {self.title}: {text}")
        if not bpy.app.background and bpy.context.window is not None:
            bpy.ops.wm.redraw_timer(type='DRAW_WIN_SWAP', iterations=1)  # show it before sdm_py blocks

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.wm.progress_end()
        if self.workspace is not None:
            self.workspace.status_text_set(None)
        return False


class OperatorError(Exception):
    """A problem with the operator's input that the user can fix; the message says how."""


def active_mesh(context):
    obj = context.active_object
    if obj is None:
        raise OperatorError("no active object: click a mesh object to make it active")
    if obj.type != 'MESH':
        raise OperatorError(f"the active object '{obj.name}' is a {obj.type.lower()}, not a mesh: "
                            "make a mesh object active (convert others with Object > Convert > Mesh)")
    return obj


class Triangles:
    """The triangles of a mesh that gets a result per corner (uv). With n-gons and `triangulate`,
    they come from a triangulated copy that replaces the mesh only by apply(), once sdm_py has
    succeeded; without `triangulate`, n-gons are refused."""

    def __init__(self, obj, triangulate):
        self.obj, self.bm, self.copy = obj, None, None
        data = arrays.MeshArrays(obj.data)
        if data.has_ngons:
            if not triangulate:
                raise OperatorError(f"mesh '{obj.data.name}' has faces of more than 3 corners: its uv is per triangle "
                                    "corner, so enable Triangulate or triangulate it first (Edit Mode, Face > Triangulate Faces)")
            self.bm = bmesh.new()
            self.bm.from_mesh(obj.data)
            bmesh.ops.triangulate(self.bm, faces=[f for f in self.bm.faces if len(f.verts) > 3])
            self.copy = bpy.data.meshes.new(obj.data.name + ".triangulated")
            self.bm.to_mesh(self.copy)
            data = arrays.MeshArrays(self.copy)
        self.data = data

    def apply(self):
        """Replaces the mesh by its triangulation (the loops the arrays' corners refer to)."""
        if self.bm is not None:
            self.bm.to_mesh(self.obj.data)
            self.obj.data.update()

    def free(self):
        if self.bm is not None:
            self.bm.free()
            bpy.data.meshes.remove(self.copy)
            self.bm = self.copy = None


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


class SdmOperator:
    """execute() for every operator: loads sdm_py, runs self.run() and reports its line, or the
    error (sdm_py's ValueError, a missing file, a bad selection) returning CANCELLED."""
    bl_options = {'REGISTER', 'UNDO'}
    title = ""
    steps = 3

    @classmethod
    def poll(cls, context):
        return context.mode == 'OBJECT'

    def execute(self, context):
        start = time.perf_counter()
        try:
            sdm = loader.load(context)
            with Progress(context, self.title, self.steps) as progress:
                line = self.run(context, sdm, progress)
        except (loader.SdmPyMissing, OperatorError, ValueError, RuntimeError, OSError) as e:
            self.report({'ERROR'}, f"SDM {self.title}: {e}")
            return {'CANCELLED'}
        self.report({'INFO'}, f"SDM {self.title}: {line} ({time.perf_counter() - start:.1f} s)")
        return {'FINISHED'}


class SDM_OT_skeleton(SdmOperator, bpy.types.Operator):
    """Curve skeleton of the active mesh (sdm_py.skeleton) as an armature or a curve object"""
    bl_idname = "sdm.skeleton"
    bl_label = "Skeleton"
    title = "skeleton"

    output: EnumProperty(
        name="Output",
        items=[('ARMATURE', "Armature", "An armature with one bone per skeleton edge, connected into chains from the "
                                        "node with most edges"),
               ('CURVE', "Curve", "A curve object with one poly spline per segment (chain between branch and end nodes)")],
        default='ARMATURE')

    def run(self, context, sdm, progress):
        obj = active_mesh(context)
        progress.step("reading the mesh")
        data = arrays.MeshArrays(obj.data)
        progress.step(f"extracting the skeleton of {len(data.V)} vertices")
        s = sdm.skeleton(data.V, data.F)
        progress.step("building the " + self.output.lower())
        nodes, edges = np.asarray(s["nodes"]), np.asarray(s["edges"])
        parts = armature.chains(len(nodes), edges)
        name = obj.name + ".skeleton"
        if self.output == 'ARMATURE':
            new = armature.build(context, name, nodes, edges)
        else:
            new = self.curve(name, nodes, parts, 0.004 * diagonal(data.V))
        new.matrix_world = obj.matrix_world
        for key in ("cycles", "ends", "branch_nodes"):
            new["sdm_" + key] = int(s[key])
        new["sdm_nodes"], new["sdm_edges"], new["sdm_segments"] = len(nodes), len(edges), len(parts)
        return (f"{len(nodes)} nodes, {len(edges)} edges in {len(parts)} segments ({s['ends']} ends, "
                f"{s['branch_nodes']} branch nodes, {s['cycles']} cycles) -> {self.output.lower()} '{new.name}'")

    def curve(self, name, nodes, parts, bevel):
        cu = bpy.data.curves.new(name, 'CURVE')
        cu.dimensions = '3D'
        cu.bevel_depth = bevel
        for path, _ in parts:
            spline = cu.splines.new('POLY')
            spline.points.add(len(path) - 1)
            co = np.hstack([nodes[path], np.ones((len(path), 1))])
            spline.points.foreach_set("co", co.astype(np.float32).reshape(-1))
        new = bpy.data.objects.new(name, cu)
        bpy.context.collection.objects.link(new)
        return new


class SDM_OT_layout(SdmOperator, bpy.types.Operator):
    """Skeleton texture map of the active mesh (sdm_py.layout): a uv layer "STM" and a checker of the layout"""
    bl_idname = "sdm.layout"
    bl_label = "STM Layout"
    title = "STM layout"
    steps = 4

    size: IntProperty(name="Atlas size", description="Side of the square atlas in texels",
                      default=1024, min=64, max=16384)
    margin: IntProperty(name="Margin", description="Texels around every rectangle", default=4, min=0, max=64)
    triangulate: BoolProperty(name="Triangulate", default=True,
                              description="Triangulate faces of more than 3 corners (the STM uv is per triangle corner)")
    checker: BoolProperty(name="Checker material", default=True,
                          description="Make an image of the layout (a checker per segment) and a material showing it "
                                      "through the STM uv, added to the object's materials and given to every face")

    def run(self, context, sdm, progress):
        obj = active_mesh(context)
        progress.step("reading the mesh")
        tris = Triangles(obj, self.triangulate)
        try:
            data = tris.data
            progress.step(f"layout of {len(data.F)} triangles at {self.size}^2")
            stm = sdm.layout(data.V, data.F, size=self.size, margin=self.margin)
            loop_uv = data.loop_uv(stm["faces"], stm["uv"])
            progress.step("writing the uv layer 'STM'")
            tris.apply()
        finally:
            tris.free()
        mesh = obj.data
        arrays.set_uv_layer(mesh, "STM", loop_uv)
        mesh["sdm_stm_coverage"] = float(stm["coverage"])
        mesh["sdm_stm_stretch"] = float(stm["stretch"])
        mesh["sdm_stm_segments"] = int(stm["segments"])
        mesh["sdm_stm_layout"] = stm["json"]
        if self.checker:
            progress.step("drawing the layout's checker")
            image = arrays.array_to_image(obj.name + " STM checker", images.layout_checker(stm["json"]))
            images.preview_material(obj, obj.name + " STM", image, "STM")
        return (f"uv layer 'STM' on {len(mesh.loops)} loops: {stm['segments']} segments, coverage "
                f"{stm['coverage']:.4f}, L2 stretch {stm['stretch']:.3f}")


PRECISIONS = [(str(b), f"{b} bits", f"Displacement quantised to {b} bits") for b in range(4, 12)] + [
    ('half', "Half float", "Displacement as 16-bit float, in model units"),
    ('float', "Float", "Displacement as 32-bit float, in model units")]


def exr_path(filepath, must_exist):
    path = bpy.path.abspath(filepath) if filepath else ""
    if not path:
        raise OperatorError("no file given: set the operator's File Path to an .exr file")
    folder = os.path.dirname(path) or "."
    if must_exist and not os.path.isfile(path):
        raise OperatorError(f"{path} does not exist: choose an SDM .exr file written by SDM Encode or `sdm encode`")
    if not must_exist and not os.path.isdir(folder):
        raise OperatorError(f"the folder {folder} does not exist: create it or choose another path")
    return path


class SDM_OT_encode(SdmOperator, bpy.types.Operator):
    """Encode the active mesh as a skeleton displacement map, an OpenEXR file (sdm_py.encode)"""
    bl_idname = "sdm.encode"
    bl_label = "SDM Encode"
    title = "encode"

    filepath: StringProperty(name="File Path", subtype='FILE_PATH', description="The .exr file to write")
    filter_glob: StringProperty(default="*.exr", options={'HIDDEN'})
    size: IntProperty(name="Map size", description="Side of the square map in texels", default=1024, min=64, max=16384)
    precision: EnumProperty(name="Precision", items=PRECISIONS, default='10',
                            description="How the displacement is stored")

    def invoke(self, context, event):
        if not self.filepath:
            obj = context.active_object
            self.filepath = "//" + bpy.path.clean_name(obj.name if obj else "mesh") + ".exr"
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    def run(self, context, sdm, progress):
        obj = active_mesh(context)
        path = exr_path(self.filepath, must_exist=False)
        progress.step("reading the mesh")
        data = arrays.MeshArrays(obj.data)
        progress.step(f"encoding {len(data.F)} triangles at {self.size}^2")
        st = sdm.encode(data.V, data.F, path, size=self.size, precision=self.precision)
        progress.step("done")
        obj["sdm_exr"] = path
        hits = st["own_hits"] + st["other_hits"]
        return (f"{path} ({os.path.getsize(path) / 1e6:.2f} MB): {st['size']}^2, {st['segments']} segments, "
                f"{hits} of {st['texels']} texel rays hit the surface, {st['base_faces']} base faces")


def segment_levels(text):
    """"3=1, 5=2" -> {3: 1, 5: 2}: the segments decoded at their own level (sdm decode --lod-segment)."""
    out = {}
    for item in text.replace(";", ",").split(","):
        if not item.strip():
            continue
        sid, eq, level = item.partition("=")
        try:
            sid, level = int(sid), int(level)
        except ValueError:
            raise OperatorError(f"segment levels: '{item.strip()}' is not of the form SEGMENT=LEVEL (e.g. 3=1)") from None
        if not eq or sid < 0 or not 0 <= level <= 6:
            raise OperatorError(f"segment levels: '{item.strip()}' needs a segment >= 0 and a level 0..6")
        out[sid] = level
    return out


class SDM_OT_decode(SdmOperator, bpy.types.Operator):
    """Rebuild a surface from a skeleton displacement map at a level of detail (sdm_py.decode), as a new mesh object,
    with an armature of the map's skeleton to pose it (SDM Pose)"""
    bl_idname = "sdm.decode"
    bl_label = "SDM Decode"
    title = "decode"
    steps = 4

    filepath: StringProperty(name="File Path", subtype='FILE_PATH', description="The SDM .exr file to read")
    filter_glob: StringProperty(default="*.exr", options={'HIDDEN'})
    level: IntProperty(name="Level of detail", default=3, min=0, max=6,
                       description="Subdivision level: 4^level triangles per base face (level 6: millions)")
    segment_levels: StringProperty(name="Segment levels", default="",
                                   description="Segments at their own level, SEGMENT=LEVEL separated by commas "
                                               "(e.g. 3=1, 5=4), as `sdm decode --lod-segment`; segment i is "
                                               "skeleton edge i (bone names: see the armature's sdm_bones)")
    make_armature: BoolProperty(name="Armature", default=True,
                                description="Also make an armature of the map's skeleton: move its bones in Pose "
                                            "Mode, then SDM Pose poses the decoded mesh through the map")

    def invoke(self, context, event):
        obj = context.active_object
        if not self.filepath and obj is not None and "sdm_exr" in obj:
            self.filepath = obj["sdm_exr"]
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    def run(self, context, sdm, progress):
        path = exr_path(self.filepath, must_exist=True)
        levels = segment_levels(self.segment_levels)
        progress.step(f"decoding {os.path.basename(path)} at level {self.level}")
        V, F = sdm.decode(path, level=self.level, segment_levels=levels)
        progress.step(f"building a mesh of {len(F)} triangles")
        name = f"{os.path.splitext(os.path.basename(path))[0]} LOD{self.level}"
        mesh = arrays.new_mesh(name, V, F, smooth=True)
        mesh["sdm_exr"], mesh["sdm_level"], mesh["sdm_segment_levels"] = path, self.level, self.segment_levels
        new = bpy.data.objects.new(name, mesh)
        context.collection.objects.link(new)
        source = context.active_object
        if source is not None and source.type == 'MESH':
            new.matrix_world = source.matrix_world  # the map holds the encoded object's local coordinates
            source.select_set(False)
        line = f"'{new.name}': {len(V)} vertices, {len(F)} triangles"
        if self.make_armature:
            progress.step("building the armature of the map's skeleton")
            k = sdm.map_skeleton(path)
            arm = armature.build(context, name + ".armature", np.asarray(k["nodes"]), np.asarray(k["edges"]), int(k["root"]))
            arm.matrix_world = new.matrix_world
            new["sdm_armature"], arm["sdm_mesh"] = arm.name, new.name
            line += f", armature '{arm.name}' of {len(k['edges'])} bones"
        new.select_set(True)
        context.view_layer.objects.active = new
        progress.step("done")
        return line


class SDM_OT_pose(SdmOperator, bpy.types.Operator):
    """Pose a decoded mesh through its skeleton displacement map as its armature (made by SDM Decode) is posed
    (sdm_py.pose): the surface follows the segments and blends at the joints, not Blender's skinning"""
    bl_idname = "sdm.pose"
    bl_label = "SDM Pose"
    title = "pose"

    @classmethod
    def poll(cls, context):
        return context.mode in ('OBJECT', 'POSE')

    def run(self, context, sdm, progress):
        obj = context.active_object
        if obj is not None and obj.type == 'ARMATURE' and obj.get("sdm_mesh") in bpy.data.objects:
            obj = bpy.data.objects[obj["sdm_mesh"]]
        if obj is None or obj.type != 'MESH' or "sdm_exr" not in obj.data or obj.get("sdm_armature") not in bpy.data.objects:
            raise OperatorError("select a mesh made by SDM Decode with its armature (or that armature)")
        arm = bpy.data.objects[obj["sdm_armature"]]
        path = exr_path(obj.data["sdm_exr"], must_exist=True)
        progress.step(f"posing {os.path.basename(path)} by '{arm.name}'")
        posed = armature.posed_skeleton(arm, sdm.map_skeleton(path)["nodes"])
        V, F = sdm.pose(path, level=int(obj.data["sdm_level"]), skeleton=posed,
                        segment_levels=segment_levels(obj.data.get("sdm_segment_levels", "")))
        if len(V) != len(obj.data.vertices):
            raise OperatorError(f"the map decodes to {len(V)} vertices but '{obj.name}' has {len(obj.data.vertices)}: "
                                "decode it again with SDM Decode")
        obj.data.vertices.foreach_set("co", V.astype(np.float32).reshape(-1))
        obj.data.update()
        progress.step("done")
        return f"'{obj.name}' posed by '{arm.name}': {len(V)} vertices"


class SDM_OT_transfer(SdmOperator, bpy.types.Operator):
    """Transfer the texture of the other selected mesh onto the active one (sdm_py.transfer): a uv layer and an image"""
    bl_idname = "sdm.transfer"
    bl_label = "Texture Transfer"
    title = "transfer"
    steps = 4

    size: IntProperty(name="Atlas size", default=1024, min=64, max=16384, description="Side of the target's atlas")
    force: BoolProperty(name="Force", default=False,
                        description="Transfer even when the two skeletons' branchings differ")
    uv_name: StringProperty(name="UV layer", default="Transfer", description="The target's new uv layer")
    triangulate: BoolProperty(name="Triangulate", default=True,
                              description="Triangulate the target's faces of more than 3 corners (its uv is per triangle corner)")
    material: BoolProperty(name="Material", default=True,
                           description="Add a material showing the transferred image to the target, given to every face")

    def run(self, context, sdm, progress):
        target = active_mesh(context)
        others = [o for o in context.selected_objects if o is not target and o.type == 'MESH']
        if len(others) != 1:
            raise OperatorError(f"{len(others)} other selected meshes: select the textured source, then the target "
                                "last (Shift-click) so that the target is active")
        source = others[0]
        progress.step("reading both meshes")
        src = arrays.MeshArrays(source.data)
        image, uv_layer = images.source_texture(source)
        uv = texture = None
        if uv_layer is not None and image is not None:
            uv, texture = src.corner_uv(uv_layer), arrays.image_to_array(image)
        tris = Triangles(target, self.triangulate)
        try:
            dst = tris.data
            what = (f"'{image.name}' through uv '{uv_layer.name}'" if texture is not None
                    else "a grey texture (the source has no uv and image)")
            progress.step(f"transferring {what} onto {len(dst.F)} triangles")
            r = sdm.transfer(src.V, src.F, dst.V, dst.F, uv=uv, texture=texture, size=self.size, force=self.force)
            loop_uv = dst.loop_uv(r["faces"], r["uv"])
            progress.step("writing the uv layer and the image")
            tris.apply()
        finally:
            tris.free()
        arrays.set_uv_layer(target.data, self.uv_name, loop_uv)
        atlas = arrays.array_to_image(f"{target.name} {self.uv_name}", r["atlas"])
        target["sdm_transfer_fit_rms"] = float(r["fit_rms"])
        target["sdm_transfer_fit_p99"] = float(r["fit_p99"])
        target["sdm_transfer_registered"] = bool(r["registered"])
        if self.material:
            progress.step("making the material")
            images.preview_material(target, f"{target.name} {self.uv_name}", atlas, self.uv_name)
        line = f"'{source.name}' -> '{target.name}': uv layer '{self.uv_name}', image '{atlas.name}' {self.size}^2"
        if texture is None:
            self.report({'WARNING'}, "the source has no uv layer or no image texture: only the correspondence "
                                     "went over (a grey image); give the source a material with an Image Texture")
        return line


classes = (SDM_OT_skeleton, SDM_OT_layout, SDM_OT_encode, SDM_OT_decode, SDM_OT_pose, SDM_OT_transfer)

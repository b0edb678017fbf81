"""Blender meshes and images as the numpy arrays sdm_py takes, and back.

sdm_py wants vertices float64 (n, 3) and triangles int32 (m, 3) indexing only used vertices. A
Blender mesh is read through its loop triangles, so quads and n-gons come as triangles, and every
triangle corner keeps the loop it came from: per-corner results (uv) go back onto those loops.
"""
import numpy as np


class MeshArrays:
    """A mesh's triangles for sdm_py: V (n, 3), F (m, 3), and for every corner of F its loop.

    vertex[i] is the Blender vertex of row i of V (loose vertices are left out, since sdm_py refuses
    vertices no face uses); loops[t, c] is the loop of corner c of triangle t; polygon[t] the
    polygon triangle t belongs to.
    """

    def __init__(self, mesh):
        mesh.calc_loop_triangles()
        m = len(mesh.loop_triangles)
        if m == 0:
            raise ValueError(f"mesh '{mesh.name}' has no faces: sdm needs a closed triangle surface")
        co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        tri_vertices = np.empty(3 * m, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", tri_vertices)
        self.loops = np.empty(3 * m, dtype=np.int32)
        mesh.loop_triangles.foreach_get("loops", self.loops)
        self.loops = self.loops.reshape(m, 3)
        self.polygon = np.empty(m, dtype=np.int32)
        mesh.loop_triangles.foreach_get("polygon_index", self.polygon)
        self.vertex, F = np.unique(tri_vertices, return_inverse=True)
        self.V = co.reshape(-1, 3)[self.vertex].astype(np.float64)
        self.F = F.reshape(m, 3).astype(np.int32)
        self.n_loops = len(mesh.loops)
        self.has_ngons = len(mesh.polygons) != m

    def corner_order(self, faces):
        """For triangles `faces` returned by sdm_py (the input's, each possibly rotated or flipped
        when the mesh was oriented outward), the column of faces[t] holding corner c of F[t]."""
        faces = np.asarray(faces)
        if faces.shape != self.F.shape:
            raise ValueError(f"sdm_py returned {faces.shape[0]} faces for the {self.F.shape[0]} it was given")
        match = faces[:, None, :] == self.F[:, :, None]  # [t, c, j]: F[t, c] == faces[t, j]
        wrong = (match.sum(axis=2) != 1).any(axis=1)
        if wrong.any():
            bad = int(np.flatnonzero(wrong)[0])
            raise ValueError(f"sdm_py's face {bad} has other corners than the mesh's: {faces[bad]} against {self.F[bad]}")
        return np.argmax(match, axis=2)

    def loop_uv(self, faces, uv):
        """Per-corner uv (m, 3, 2) of sdm_py's `faces` as one (u, v) per loop of the mesh."""
        order = self.corner_order(faces)
        uv = np.asarray(uv, dtype=np.float64).reshape(-1, 3, 2)
        per_corner = np.take_along_axis(uv, order[:, :, None], axis=1)  # (m, 3, 2) in F's corner order
        out = np.zeros((self.n_loops, 2), dtype=np.float64)
        out[self.loops.reshape(-1)] = per_corner.reshape(-1, 2)
        return out

    def corner_uv(self, uv_layer):
        """A Blender uv layer read per corner of F: (m, 3, 2), as sdm_py.transfer takes it."""
        data = np.empty(2 * self.n_loops, dtype=np.float32)
        uv_layer.data.foreach_get("uv", data)
        return data.reshape(-1, 2)[self.loops].astype(np.float64)


def set_uv_layer(mesh, name, loop_uv):
    """Creates (or overwrites) the uv layer `name` with one (u, v) per loop and makes it active."""
    layer = mesh.uv_layers.get(name) or mesh.uv_layers.new(name=name)
    if layer is None:
        raise ValueError(f"mesh '{mesh.name}' has the most uv layers Blender allows: remove one to make room for '{name}'")
    layer.data.foreach_set("uv", np.ascontiguousarray(loop_uv, dtype=np.float32).reshape(-1))
    mesh.uv_layers.active = layer
    mesh.update()
    return layer


def new_mesh(name, V, F, smooth=False):
    """A Blender mesh of triangles F (m, 3) over vertices V (n, 3)."""
    import bpy

    V = np.ascontiguousarray(V, dtype=np.float32)
    F = np.ascontiguousarray(F, dtype=np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(V))
    mesh.vertices.foreach_set("co", V.reshape(-1))
    mesh.loops.add(3 * len(F))
    mesh.loops.foreach_set("vertex_index", F.reshape(-1))
    mesh.polygons.add(len(F))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(F), 3, dtype=np.int32))
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:  # derived since Blender 4.0
        mesh.polygons.foreach_set("loop_total", np.full(len(F), 3, dtype=np.int32))
    if smooth:
        mesh.polygons.foreach_set("use_smooth", np.ones(len(F), dtype=bool))
    mesh.update(calc_edges=True)
    mesh.validate()
    return mesh


def image_to_array(image):
    """A Blender image's pixels as uint8 (height, width, 4), the top row first (sdm's images)."""
    w, h = image.size
    if w == 0 or h == 0:
        raise ValueError(f"image '{image.name}' has no pixels (its file {image.filepath!r} may be missing): "
                         "reload or repack it, or remove it from the material")
    px = np.empty(w * h * image.channels, dtype=np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(h, w, image.channels)
    if image.channels == 3:
        px = np.concatenate([px, np.ones((h, w, 1), dtype=np.float32)], axis=2)
    elif image.channels != 4:
        grey = px[:, :, :1]
        px = np.concatenate([grey, grey, grey, np.ones((h, w, 1), dtype=np.float32)], axis=2)
    return np.ascontiguousarray(np.round(np.clip(px[::-1], 0, 1) * 255).astype(np.uint8))


def array_to_image(name, rgba):
    """A packed Blender image of uint8 (height, width, 4) pixels, the top row first; an existing
    image of that name is overwritten (replaced when its size differs)."""
    import bpy

    rgba = np.asarray(rgba)
    h, w = rgba.shape[:2]
    image = bpy.data.images.get(name)
    if image is not None and tuple(image.size) != (w, h):
        bpy.data.images.remove(image)
        image = None
    if image is None:
        image = bpy.data.images.new(name, width=w, height=h, alpha=True)
    image.pixels.foreach_set((rgba[::-1].astype(np.float32) / 255.0).reshape(-1))
    image.pack()
    return image

"""Pictures the add-on makes: a checker of an STM layout (sdm_py.layout returns no atlas image) and
a preview material that shows an image through a named uv layer."""
import colorsys
import json

import numpy as np


def footprints(layout_json):
    """Every segment's rectangle in atlas texels as placed: (x, y, width, height), y up like v.
    A rotated rectangle lies with its sides swapped; its margin is outside these bounds."""
    j = json.loads(layout_json) if isinstance(layout_json, str) else layout_json
    out = []
    for s in j["segments"]:
        x, y, w, h = s["rect"]
        out.append((x, y, h, w) if s.get("rotated") else (x, y, w, h))
    return out


def layout_coverage(layout_json):
    """Packed area over atlas area, each rectangle with its margin: the layout's `coverage`."""
    j = json.loads(layout_json) if isinstance(layout_json, str) else layout_json
    m, size = j["margin"], j["size"]
    return sum((w + 2 * m) * (h + 2 * m) for _, _, w, h in footprints(j)) / float(size * size)


def layout_checker(layout_json, square=16):
    """uint8 (size, size, 4), the top row first: every segment's rectangle in its own hue with a
    checker of `square` texels, margins and free atlas space dark grey."""
    j = json.loads(layout_json)
    size = int(j["size"])
    img = np.full((size, size, 4), 48, dtype=np.uint8)  # row r is v = (r + 0.5) / size from the bottom
    img[:, :, 3] = 255
    ys, xs = np.mgrid[0:size, 0:size]
    light = ((xs // square + ys // square) % 2 == 0)
    rects = footprints(j)
    for i, (x, y, w, h) in enumerate(rects):
        hue = (i * 0.618034) % 1.0  # golden-ratio steps: neighbours' hues differ
        dark = np.array(colorsys.hsv_to_rgb(hue, 0.75, 0.55)) * 255
        bright = np.array(colorsys.hsv_to_rgb(hue, 0.35, 0.95)) * 255
        sl = (slice(y, y + h), slice(x, x + w))
        img[sl[0], sl[1], :3] = np.where(light[sl][:, :, None], bright, dark).astype(np.uint8)
    return np.ascontiguousarray(img[::-1])


def preview_material(obj, name, image, uv_name):
    """A material `name` that shows `image` through the uv layer `uv_name`, appended to the object's
    slots (its other materials stay) and given to every face."""
    import bpy

    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    tex = nt.nodes.new("ShaderNodeTexImage")
    uv = nt.nodes.new("ShaderNodeUVMap")
    uv.uv_map = uv_name
    tex.image = image
    tex.extension = 'EXTEND'  # seam triangles reach a little past their rectangle, some past the atlas
    out.location, bsdf.location, tex.location, uv.location = (300, 0), (0, 0), (-350, 0), (-600, 0)
    nt.links.new(uv.outputs["UV"], tex.inputs["Vector"])
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    nt.nodes.active = tex  # what the Solid viewport's Texture colour shows
    mesh = obj.data
    index = mesh.materials.find(mat.name)
    if index < 0:
        mesh.materials.append(mat)
        index = len(mesh.materials) - 1
    mesh.polygons.foreach_set("material_index", np.full(len(mesh.polygons), index, dtype=np.int32))
    obj.active_material_index = index
    mesh.update()
    return mat


def source_texture(obj):
    """The image a textured object shows and the uv layer it is shown through: the Image Texture node
    feeding the active material's Base Color (else its first Image Texture node), through the UV Map
    node on its Vector input, else the uv layer that renders (Blender's default); (None, None)
    when the object shows no image."""
    mat = obj.active_material
    if mat is None or not mat.use_nodes:
        return None, None
    nodes = [n for n in mat.node_tree.nodes if n.type == 'TEX_IMAGE' and n.image is not None]
    if not nodes:
        return None, None
    node = next((n for n in nodes if any(link.to_socket.name == "Base Color" for link in n.outputs["Color"].links)),
                nodes[0])
    layers = obj.data.uv_layers
    layer = next((layer for layer in layers if layer.active_render), layers.active)
    vector = node.inputs["Vector"]
    if vector.is_linked and vector.links[0].from_node.type == 'UVMAP':
        layer = layers.get(vector.links[0].from_node.uv_map) or layer
    return node.image, layer

"""Tests of the Blender add-on blender/sdm_blender (run by CTest as blender.addon):

    blender -b --factory-startup --python tests/blender/test_addon.py -- [--sdm-py DIR] [--examples DIR]

--sdm-py is the folder holding sdm_py (set as the add-on's preference; default: the add-on's own
default, build/python of this repository), --examples the folder holding spot/ (default:
examples/data of this repository, else ../shared/models beside it). The add-on is loaded from the
repository. Every operator's result is compared with sdm_py called directly on the same arrays
(the test reads them from Blender itself) or measured: uv per loop and the layout's coverage,
bone and edge counts, the decoded surface's distance to the input (BVH nearest points), the
transferred image pixel for pixel; the error paths must report an ERROR and change nothing.
"""
import argparse
import json
import subprocess
import math
import os
import sys
import tempfile
import time
import traceback

import addon_utils
import bpy
import numpy as np
from mathutils import Matrix, Vector
from mathutils.bvhtree import BVHTree

sys.dont_write_bytecode = True  # keep __pycache__ out of the source tree
REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
ADDON = "sdm_blender"


def check(condition, what):
    print(("ok    " if condition else "FAIL  ") + what, flush=True)
    if not condition:
        raise AssertionError(what)


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="test_addon.py")
    p.add_argument("--sdm-py", default="", help="folder holding sdm_py")
    p.add_argument("--examples", default="", help="folder holding spot/spot_triangulated.obj")
    p.add_argument("--sdm", default="", help="the sdm command, to compare SDM Pose and segment levels with "
                                            "`sdm pose` and `sdm decode --lod-segment` (skipped without it)")
    return p.parse_args(argv)


def spot_obj(examples):
    for folder in ([examples] if examples else []) + [os.path.join(REPO, "examples", "data"),
                                                      os.path.join(REPO, "..", "shared", "models")]:
        path = os.path.join(folder, "spot", "spot_triangulated.obj")
        if os.path.isfile(path):
            return path
    raise FileNotFoundError("spot/spot_triangulated.obj not found in examples/data or ../shared/models: pass --examples DIR")


# ---- the test's own reading of Blender data (not the add-on's) ---------------------------------

def triangles(mesh):
    """V float64 (n, 3), F int32 (m, 3) and the loop of every corner, for a mesh of triangles only."""
    check(all(len(p.vertices) == 3 for p in mesh.polygons), f"'{mesh.name}' is made of triangles")
    V = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    loops = np.array([list(p.loop_indices) for p in mesh.polygons], dtype=np.int64)
    F = np.array([list(p.vertices) for p in mesh.polygons], dtype=np.int32)
    return V, F, loops


def loop_uv(mesh, name):
    layer = mesh.uv_layers.get(name)
    check(layer is not None, f"'{mesh.name}' has a uv layer '{name}'")
    uv = np.empty(2 * len(mesh.loops), dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2).astype(np.float64)


def per_loop(faces, F, loops, uv, n_loops):
    """sdm_py's per-corner uv of `faces` (the same triangles as F, corners possibly rotated) per loop."""
    out = np.full((n_loops, 2), np.nan)
    for t in range(len(F)):
        for c in range(3):
            j = int(np.flatnonzero(faces[t] == F[t, c])[0])
            out[loops[t, c]] = uv[t, j]
    return out


def pixels(image):
    w, h = image.size
    px = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    return np.round(px.reshape(h, w, 4)[::-1] * 255).astype(np.uint8)  # top row first, as sdm's images


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def surface_samples(V, F, n, seed):
    """n points spread uniformly by area over the triangle mesh (V, F)."""
    rng = np.random.default_rng(seed)
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    t = rng.choice(len(F), size=n, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(n))[:, None], rng.random(n)[:, None]
    return (1 - r1) * a[t] + r1 * (1 - r2) * b[t] + r1 * r2 * c[t]


def distances(points, V, F):
    """Distance of every point to the nearest point of the triangle mesh (V, F)."""
    tree = BVHTree.FromPolygons([tuple(v) for v in V], F.tolist())
    d = np.empty(len(points))
    for i, p in enumerate(points):
        d[i] = tree.find_nearest(tuple(p))[3]
    return d


class Stub:
    """Stands in for an operator instance to call its execute() directly and see what it returns
    and reports (bpy.ops turns an ERROR report into a RuntimeError and keeps the return value)."""

    def __init__(self, cls, **props):
        self._cls, self.reports = cls, []
        self.__dict__.update(props)

    def __getattr__(self, name):
        attr = getattr(self._cls, name)
        return attr.__get__(self) if callable(attr) and not isinstance(attr, type) else attr

    def report(self, kinds, message):
        self.reports.append((set(kinds), message))


def activate(*objects):
    for o in bpy.context.selected_objects:
        o.select_set(False)
    for o in objects:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objects[-1]


def refused(op, needle, **props):
    """bpy.ops.sdm.<op>(**props) must raise the ERROR report containing `needle` and create nothing."""
    before = (set(bpy.data.objects), set(bpy.data.meshes), set(bpy.data.images))
    try:
        getattr(bpy.ops.sdm, op)(**props)
        check(False, f"sdm.{op} refuses ({needle})")
    except RuntimeError as e:
        msg = str(e)
        check(needle in msg, f"sdm.{op} reports: {msg if len(msg) <= 110 else msg[:110] + '...'}")
    after = (set(bpy.data.objects), set(bpy.data.meshes), set(bpy.data.images))
    check(before == after, f"sdm.{op} refused: no object, mesh or image made")


# ---- the checks --------------------------------------------------------------------------------

def test_errors(spot, sdm_py, operators):
    activate(bpy.data.objects["Camera"])
    refused("layout", "not a mesh")
    stub = Stub(operators.SDM_OT_layout, size=1024, margin=4, triangulate=True, checker=True)
    result = operators.SDM_OT_layout.execute(stub, bpy.context)
    check(result == {'CANCELLED'} and stub.reports and stub.reports[-1][0] == {'ERROR'},
          f"layout on a camera returns {result} with an ERROR report")
    # A fin (a third face on an edge of Spot) is non-manifold: sdm_py's ValueError, shown as an ERROR.
    V, F, _ = triangles(spot.data)
    fin_V = np.vstack([V, V[F[0, 0]] + 0.05])
    fin_F = np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]])
    mesh = bpy.data.meshes.new("fin")
    mesh.from_pydata(fin_V.tolist(), [], fin_F.tolist())
    fin = bpy.data.objects.new("fin", mesh)
    bpy.context.collection.objects.link(fin)
    activate(fin)
    refused("skeleton", "non-manifold")
    stub = Stub(operators.SDM_OT_layout, size=1024, margin=4, triangulate=True, checker=True)
    result = operators.SDM_OT_layout.execute(stub, bpy.context)
    check(result == {'CANCELLED'} and "non-manifold" in stub.reports[-1][1] and "STM" not in mesh.uv_layers,
          f"layout on the fin returns {result}, no uv layer: {stub.reports[-1][1][:90]}...")
    bpy.data.objects.remove(fin)
    bpy.data.meshes.remove(mesh)
    activate(spot)
    refused("encode", "does not exist", filepath="/nonexistent-folder/spot.exr")
    prefs = bpy.context.preferences.addons[ADDON].preferences
    kept, prefs.sdm_py_folder = prefs.sdm_py_folder, "/nonexistent-sdm-py"
    refused("skeleton", "does not exist")
    prefs.sdm_py_folder = kept


def test_skeleton(spot, sdm_py):
    V, F, _ = triangles(spot.data)
    ref = sdm_py.skeleton(V, F)
    nodes, edges = ref["nodes"], ref["edges"]
    activate(spot)
    check(bpy.ops.sdm.skeleton(output='ARMATURE') == {'FINISHED'}, "sdm.skeleton (armature) finished")
    arm = bpy.data.objects[spot.name + ".skeleton"]
    bones = arm.data.bones
    check(len(bones) == len(edges), f"armature: {len(bones)} bones = sdm_py.skeleton's {len(edges)} edges")
    want = {tuple(sorted(map(int, e))) for e in edges}
    got = set()
    for b in bones:
        a = int(np.argmin(np.linalg.norm(nodes - np.array(b.head_local), axis=1)))
        c = int(np.argmin(np.linalg.norm(nodes - np.array(b.tail_local), axis=1)))
        err = max(np.linalg.norm(nodes[a] - b.head_local), np.linalg.norm(nodes[c] - b.tail_local))
        got.add(tuple(sorted((a, c))) if err < 1e-5 else None)
    check(got == want, f"every bone joins the two nodes of one skeleton edge (within 1e-5), each edge once")
    roots = {tuple(np.round(b.head_local, 6)) for b in bones if b.parent is None}
    connected = all((b.head_local - b.parent.tail_local).length < 1e-6 for b in bones if b.parent is not None)
    check(len(roots) == 1 and connected,
          f"the bones hang from one node ({sum(b.parent is None for b in bones)} root bones), each from its parent's tail")
    check(bpy.ops.sdm.skeleton(output='CURVE') == {'FINISHED'}, "sdm.skeleton (curve) finished")
    curve = bpy.data.objects[spot.name + ".skeleton.001"]
    splines = curve.data.splines
    pieces = sum(len(s.points) - 1 for s in splines)
    check(pieces == len(edges) and len(splines) == curve["sdm_segments"],
          f"curve: {len(splines)} splines (segments) of {pieces} pieces = {len(edges)} edges")
    ends = np.count_nonzero(np.bincount(edges.reshape(-1)) == 1)
    check(ends == ref["ends"], f"the skeleton's {ref['ends']} ends are its nodes of one edge")


def test_layout(spot, sdm_py):
    activate(spot)
    check(bpy.ops.sdm.layout(size=1024) == {'FINISHED'}, "sdm.layout finished")
    mesh = spot.data
    V, F, loops = triangles(mesh)
    ref = sdm_py.layout(V, F, size=1024)
    uv = loop_uv(mesh, "STM")
    want = per_loop(ref["faces"], F, loops, ref["uv"], len(mesh.loops))
    check(not np.isnan(want).any(), f"sdm_py's layout gives every one of the {len(mesh.loops)} loops a uv")
    err = np.abs(uv - want).max()
    check(err < 1e-6, f"uv layer 'STM' on every loop equals sdm_py.layout's corner uv (max difference {err:.1e})")
    cov = mesh["sdm_stm_coverage"]
    check(abs(cov - ref["coverage"]) < 1e-9, f"coverage {cov:.6f} = sdm_py.layout's {ref['coverage']:.6f} (1e-9)")
    j = json.loads(mesh["sdm_stm_layout"])
    m, S = j["margin"], j["size"]
    rects = [(x, y, h, w) if s["rotated"] else (x, y, w, h) for s in j["segments"] for x, y, w, h in [s["rect"]]]
    from_rects = sum((w + 2 * m) * (h + 2 * m) for _, _, w, h in rects) / S ** 2
    check(abs(from_rects - cov) < 1e-9, f"coverage = the stored layout's rectangles with margins over the atlas ({from_rects:.6f})")
    # Every corner inside [0, 1], but for seam triangles: unwrapped past their rectangle's end (the
    # atlas holds them clipped, once on each side), so corners reach past the rectangle and, at
    # the atlas border, past [0, 1].
    outside = ((uv < 0) | (uv > 1)).any(axis=1)
    faces_out = np.flatnonzero(outside[loops].any(axis=1))
    overhang = 0
    for t in faces_out:
        x, y, w, h = rects[ref["face_segment"][t]]
        p = uv[loops[t]] * S
        overhang += bool(p[:, 0].min() < x - m or p[:, 0].max() > x + w + m or p[:, 1].min() < y - m or p[:, 1].max() > y + h + m)
    check(overhang == len(faces_out) and len(faces_out) < 0.01 * len(F),
          f"uv in [0, 1] on {len(uv) - outside.sum()} of {len(uv)} loops; the other {outside.sum()} on "
          f"{len(faces_out)} seam triangles reaching past their rectangle (< 1 % of faces), "
          f"uv {uv.min():.4f}..{uv.max():.4f}")
    image = bpy.data.images.get(spot.name + " STM checker")
    check(image is not None and tuple(image.size) == (1024, 1024), "the layout's checker image, 1024^2")
    return ref


def test_round_trip(spot, sdm_py, folder):
    path = os.path.join(folder, "spot.exr")
    activate(spot)
    check(bpy.ops.sdm.encode(filepath=path, size=1024) == {'FINISHED'} and os.path.getsize(path) > 0,
          f"sdm.encode wrote {os.path.getsize(path)} bytes")
    check(bpy.ops.sdm.decode(filepath=path, level=3) == {'FINISHED'}, "sdm.decode (level 3) finished")
    dec = bpy.context.active_object
    D, G = sdm_py.decode(path, level=3)
    _, G0 = sdm_py.decode(path, level=0)
    BV, BF, _ = triangles(dec.data)
    check(len(BV) == len(D) and len(BF) == len(G) == 64 * len(G0),
          f"decoded object: {len(BV)} vertices = sdm_py.decode's, {len(BF)} triangles = 64 x {len(G0)} base faces")
    check(np.abs(BV - D).max() < 1e-6 * diagonal(D) + 1e-6 and np.array_equal(BF, G),
          "its vertices and triangles are sdm_py.decode's")
    check(dec.matrix_world == spot.matrix_world, "placed as the encoded object")
    V, F, _ = triangles(spot.data)
    diag = diagonal(V)
    # As `sdm roundtrip` measures: points spread evenly over each surface, to the other's nearest point.
    n = 20000
    there = distances(surface_samples(BV, BF, n, 1), V, F) / diag
    back = distances(surface_samples(V, F, n, 2), BV, BF) / diag
    rms = math.sqrt((np.sum(there ** 2) + np.sum(back ** 2)) / (2 * n))
    worst = max(there.max(), back.max(), (distances(BV, V, F) / diag).max(), (distances(V, BV, BF) / diag).max())
    check(rms <= 5e-4, f"decoded against input over {n} points on each: RMS {100 * rms:.4f} % of the diagonal "
                       f"(<= 0.05 %), largest distance (points and vertices) {100 * worst:.3f} %")
    return path


def sdm_mesh(sdm_py, sdm, *args):
    """The mesh `sdm ARGS -o OUT.obj` writes, as (V, F)."""
    with tempfile.TemporaryDirectory() as folder:
        out = os.path.join(folder, "out.obj")
        subprocess.run([sdm, *args, "-o", out], check=True, stdout=subprocess.DEVNULL)
        return sdm_py.read_mesh(out)


def test_segment_levels(spot, sdm_py, path, sdm):
    activate(spot)
    check(bpy.ops.sdm.decode(filepath=path, level=1, segment_levels="0=3, 2=2", make_armature=False) == {'FINISHED'},
          "sdm.decode (level 1, segment 0 at 3 and 2 at 2) finished")
    dec = bpy.context.active_object
    BV, BF, _ = triangles(dec.data)
    V, F = sdm_mesh(sdm_py, sdm, "decode", path, "--lod", "1", "--lod-segment", "0=3", "--lod-segment", "2=2")
    n1 = len(sdm_py.decode(path, level=1)[1])
    err = np.abs(BV - V).max() / diagonal(V) if len(BV) == len(V) else math.inf
    check(len(BF) > n1 and np.array_equal(BF, F) and err < 1e-6,
          f"per-segment levels: {len(BF)} triangles (all at level 1: {n1}), the mesh of `sdm decode --lod-segment` "
          f"(largest vertex difference {err:.1e} of the diagonal)")
    bpy.data.objects.remove(dec)


def test_pose(spot, sdm_py, path, sdm):
    activate(spot)
    check(bpy.ops.sdm.decode(filepath=path, level=2) == {'FINISHED'}, "sdm.decode (level 2) finished")
    dec = bpy.context.active_object
    arm = bpy.data.objects[dec["sdm_armature"]]
    k = sdm_py.map_skeleton(path)
    nodes, edges = np.asarray(k["nodes"]), np.asarray(k["edges"])
    check(len(arm.data.bones) == len(edges), f"armature '{arm.name}': a bone per segment ({len(edges)})")
    # A leg: the chain holding the lowest end node; its bone whose head is the chain's middle node.
    ends = {n for n in range(len(nodes)) if np.count_nonzero(edges == n) == 1}
    foot = min(ends, key=lambda n: nodes[n, 1])
    heads = {name: tuple(ab) for name, ab in arm["sdm_bones"].items()}
    from sdm_blender import armature
    leg = next(chain for chain, _ in armature.chains(len(nodes), edges) if foot in chain)
    middle = leg[len(leg) // 2]
    name = next(n for n, (a, _) in heads.items() if a == middle)
    axis = np.array([1.0, 0.0, 0.0])
    pb = arm.pose.bones[name]
    h = pb.head.copy()
    turn = Matrix.Translation(h) @ Matrix.Rotation(math.radians(45), 4, Vector(axis)) @ Matrix.Translation(-h)
    pb.matrix = turn @ pb.matrix
    bpy.context.view_layer.update()
    rest, _, _ = triangles(dec.data)
    activate(dec)
    check(bpy.ops.sdm.pose() == {'FINISHED'}, f"sdm.pose finished (bone {name} turned 45 degrees about x at node {middle})")
    BV, BF, _ = triangles(dec.data)
    V, F = sdm_mesh(sdm_py, sdm, "pose", path, "--lod", "2", "--rotate", f"{middle}=1,0,0,45")
    d = diagonal(V)
    err = np.abs(BV - V).max() / d
    moved = np.linalg.norm(BV - rest, axis=1).max() / d
    check(np.array_equal(BF, F) and err < 1e-6 and moved > 0.01,
          f"posed by the armature as `sdm pose --rotate {middle}=1,0,0,45`: largest vertex difference {err:.1e} "
          f"of the diagonal (< 1e-6); the leg moved up to {100 * moved:.1f} %")
    bpy.data.objects.remove(dec)
    bpy.data.objects.remove(arm)


def test_transfer(spot, sdm_py, path):
    activate(spot)
    check(bpy.ops.sdm.decode(filepath=path, level=2) == {'FINISHED'}, "sdm.decode (level 2) finished")
    target = bpy.context.active_object
    activate(spot, target)  # the textured source selected, the target active
    spot.active_material_index = spot.data.materials.find("Default_OBJ")  # Spot's texture, not the STM checker
    size = 512
    check(bpy.ops.sdm.transfer(size=size) == {'FINISHED'}, "sdm.transfer finished")
    Vs, Fs, Ls = triangles(spot.data)
    src_uv = loop_uv(spot.data, "UVMap")[Ls]
    node = next(n for n in spot.data.materials["Default_OBJ"].node_tree.nodes if n.type == 'TEX_IMAGE')
    texture = pixels(node.image)
    Vt, Ft, Lt = triangles(target.data)
    ref = sdm_py.transfer(Vs, Fs, Vt, Ft, uv=src_uv, texture=texture, size=size)
    image = bpy.data.images[target.name + " Transfer"]
    got = pixels(image)
    check(got.shape == ref["atlas"].shape, f"transferred image {got.shape} as sdm_py.transfer's atlas")
    differ = np.count_nonzero((got != ref["atlas"]).any(axis=2))
    check(differ == 0, f"the transferred image equals sdm_py.transfer's atlas pixel for pixel ({differ} pixels differ)")
    colored = np.count_nonzero(np.ptp(ref["atlas"][:, :, :3].astype(int), axis=2) > 30)
    check(colored > 0.05 * size * size, f"it carries Spot's colours: {colored} saturated pixels")
    uv = loop_uv(target.data, "Transfer")
    want = per_loop(ref["faces"], Ft, Lt, ref["uv"], len(target.data.loops))
    err = np.abs(uv - want).max()
    check(err < 1e-6, f"uv layer 'Transfer' on every loop equals sdm_py.transfer's (max difference {err:.1e})")


def main():
    args = arguments()
    start = time.perf_counter()
    sys.path.insert(0, os.path.join(REPO, "blender"))
    mod = addon_utils.enable(ADDON, default_set=True, handle_error=None)
    check(mod is not None and mod.__file__.startswith(os.path.join(REPO, "blender")), f"add-on loaded from {REPO}/blender")
    prefs = bpy.context.preferences.addons[ADDON].preferences
    if args.sdm_py:
        prefs.sdm_py_folder = args.sdm_py
    from sdm_blender import loader, operators
    kind, line = loader.describe()
    check(kind == 'INFO', f"sdm_py found: {line}")
    import sdm_py
    bpy.ops.wm.obj_import(filepath=spot_obj(args.examples))
    spot = bpy.context.active_object
    check(spot.type == 'MESH' and len(spot.data.vertices) > 1000, f"Spot imported: {len(spot.data.vertices)} vertices")
    for name, run in [("errors", lambda: test_errors(spot, sdm_py, operators)),
                      ("skeleton", lambda: test_skeleton(spot, sdm_py)),
                      ("layout", lambda: test_layout(spot, sdm_py))]:
        t = time.perf_counter()
        run()
        print(f"      ({name}: {time.perf_counter() - t:.1f} s)")
    with tempfile.TemporaryDirectory() as folder:
        t = time.perf_counter()
        path = test_round_trip(spot, sdm_py, folder)
        print(f"      (round trip: {time.perf_counter() - t:.1f} s)")
        if args.sdm:
            t = time.perf_counter()
            test_segment_levels(spot, sdm_py, path, args.sdm)
            test_pose(spot, sdm_py, path, args.sdm)
            print(f"      (segment levels and pose: {time.perf_counter() - t:.1f} s)")
        else:
            print("skip  SDM Pose and segment levels against the sdm command: no --sdm given")
        t = time.perf_counter()
        test_transfer(spot, sdm_py, path)
        print(f"      (transfer: {time.perf_counter() - t:.1f} s)")
    addon_utils.disable(ADDON, default_set=True, handle_error=None)
    check(not hasattr(bpy.types, "SDM_OT_layout"), "add-on disabled: its operators unregistered")
    print(f"blender {bpy.app.version_string}, sdm_py {sdm_py.__version__}: all add-on checks passed "
          f"in {time.perf_counter() - start:.1f} s")


if __name__ == "__main__":
    try:
        main()
    except Exception:  # Blender exits 0 after an uncaught exception: make the failure the exit code
        traceback.print_exc()
        sys.exit(1)

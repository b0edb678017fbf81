"""Tests of the Python module sdm_py on numpy arrays (run by CTest as python.module).

Each check is a property with a number derived from the geometry: a capsule built here (radius r,
axis from x = -h to x = h) has an analytic surface and axis; Spot (examples/data) transferred onto a
moved and scaled copy of itself has the exact correspondence vertex i -> vertex i.
"""
import os
import sys
import tempfile

import numpy as np
import sdm_py

R, H = 0.5, 1.0  # capsule radius, half length of its axis


def capsule(rings=24, sectors=48):
    """Closed capsule: pole, hemisphere rings, cylinder rings, hemisphere rings, pole."""
    profile = []  # (x, radius) from the -x pole to the +x pole
    for i in range(1, rings // 2 + 1):
        a = np.pi / 2 * (1 - i / (rings // 2))
        profile.append((-H - R * np.sin(a), R * np.cos(a)))
    for i in range(1, 8):
        profile.append((-H + 2 * H * i / 8, R))
    for i in range(0, rings // 2):
        a = np.pi / 2 * i / (rings // 2)
        profile.append((H + R * np.sin(a), R * np.cos(a)))
    V = [(-H - R, 0, 0)]
    for x, rad in profile:
        for s in range(sectors):
            t = 2 * np.pi * s / sectors
            V.append((x, rad * np.cos(t), rad * np.sin(t)))
    V.append((H + R, 0, 0))
    F = []
    n = len(profile)
    ring = lambda k, s: 1 + k * sectors + s % sectors
    for s in range(sectors):
        F.append((0, ring(0, s + 1), ring(0, s)))
        F.append((len(V) - 1, ring(n - 1, s), ring(n - 1, s + 1)))
        for k in range(n - 1):
            F.append((ring(k, s), ring(k, s + 1), ring(k + 1, s + 1)))
            F.append((ring(k, s), ring(k + 1, s + 1), ring(k + 1, s)))
    return np.array(V, dtype=np.float64), np.array(F, dtype=np.int32)


def capsule_distance(P):
    """Distance of points to the capsule's surface: |distance to the axis segment - r|."""
    x = np.clip(P[:, 0], -H, H)
    foot = np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=1)
    return np.abs(np.linalg.norm(P - foot, axis=1) - R)


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def check(condition, what):
    print(("ok    " if condition else "FAIL  ") + what)
    if not condition:
        sys.exit(1)


def test_skeleton(V, F):
    s = sdm_py.skeleton(V, F)
    nodes = s["nodes"]
    off_axis = np.linalg.norm(nodes[:, 1:], axis=1).max()
    check(s["cycles"] == 0 and s["ends"] == 2, f"capsule skeleton: {s['cycles']} cycles, {s['ends']} ends (0 and 2)")
    check(off_axis < 0.05 * R, f"capsule skeleton nodes within {off_axis:.2e} of the axis (< 0.05 r)")
    check(nodes[:, 0].min() < -0.8 * H and nodes[:, 0].max() > 0.8 * H,
          f"skeleton spans x {nodes[:, 0].min():.3f}..{nodes[:, 0].max():.3f} (beyond +-0.8 h)")
    check(s["vertex_node"].shape == (len(V),) and s["vertex_node"].max() < len(nodes), "a node for every vertex")
    return s


def test_layout(V, F, s):
    lay = sdm_py.layout(V, F, size=512, skeleton=s)
    uv = lay["uv"]
    check(uv.shape == (len(F), 3, 2), f"uv per face corner {uv.shape}")
    check(uv.min() >= 0 and uv.max() <= 1, f"uv within [0, 1] ({uv.min():.3f}..{uv.max():.3f})")
    check(1 <= lay["stretch"] < 1.5, f"capsule layout L2 stretch {lay['stretch']:.3f} (1 is ideal, < 1.5)")
    check(np.array_equal(np.sort(lay["faces"], axis=1), np.sort(F, axis=1)), "layout faces are the input's, in order")


def test_maps(V, F, folder):
    path = os.path.join(folder, "capsule.exr")
    stats = sdm_py.encode(V, F, path, size=512)
    hits = stats["own_hits"] + stats["other_hits"]
    check(os.path.getsize(path) > 0 and hits > 0.9 * stats["texels"],
          f"encoded: {hits} of {stats['texels']} texel rays cross the surface (> 90 %)")
    D, G = sdm_py.decode(path, level=3)
    d = capsule_distance(D) / diagonal(V)
    check(len(G) == 4 ** 3 * stats["base_faces"], f"level 3: {len(G)} triangles = 64 per base face")
    check(np.sqrt(np.mean(d ** 2)) < 5e-4 and d.max() < 5e-3,
          f"decoded points from the analytic capsule: RMS {100 * np.sqrt(np.mean(d ** 2)):.4f} %, "
          f"largest {100 * d.max():.4f} % of the diagonal (< 0.05 %, < 0.5 %)")


def test_segment_levels_and_pose(path):
    rest_V, rest_F = sdm_py.decode(path, level=2)
    k = sdm_py.map_skeleton(path)
    nodes, edges = k["nodes"], k["edges"]
    # One segment at level 3, the others at 1: more triangles than all at 1, fewer than all at 3.
    n1 = len(sdm_py.decode(path, level=1)[1])
    n3 = len(sdm_py.decode(path, level=3)[1])
    mixed = len(sdm_py.decode(path, level=1, segment_levels={0: 3})[1])
    check(n1 < mixed < n3, f"segment 0 at level 3, the others at 1: {n1} < {mixed} < {n3} triangles")
    # The rest pose given back is the decode itself.
    P, G = sdm_py.pose(path, level=2, skeleton={"nodes": nodes})
    check(np.array_equal(G, rest_F) and np.abs(P - rest_V).max() == 0, "the rest pose decodes as decode does")
    # A node inside the chain turned 60 degrees about z: the points beyond 2 r of it on the side that
    # moved follow the exact rigid motion, those on the other side stay.
    degree = np.bincount(edges.reshape(-1), minlength=len(nodes))
    inner = [i for i in range(len(nodes)) if degree[i] == 2]
    pivot = min(inner, key=lambda i: abs(nodes[i, 0] - 0.3))
    c = nodes[pivot]
    a = np.radians(60)
    rot = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    P, _ = sdm_py.pose(path, level=2, rotate=[(pivot, np.array([0.0, 0.0, 1.0]), 60.0)])
    rigid = (rest_V - c) @ rot.T + c
    far = np.abs(rest_V[:, 0] - c[0]) > 2 * R
    moved = np.linalg.norm(P - rest_V, axis=1) > 1e-9
    side = far & moved
    d = diagonal(rest_V)
    err_moved = np.abs(P[side] - rigid[side]).max() / d
    err_still = np.abs(P[far & ~moved] - rest_V[far & ~moved]).max() / d if np.any(far & ~moved) else 0.0
    sides = np.sign(rest_V[side, 0] - c[0])
    check(side.sum() > 100 and np.all(sides == sides[0]) and err_moved < 1e-9 and err_still == 0,
          f"node {pivot} turned 60 degrees: {side.sum()} points beyond 2 r on one side move rigidly "
          f"(largest deviation {err_moved:.1e} of the diagonal), the other side stays")
    try:
        sdm_py.pose(path, rotate=[(len(nodes), np.array([0.0, 0.0, 1.0]), 10.0)])
        check(False, "a node out of range is refused")
    except ValueError as e:
        check("node" in str(e), f"a node out of range is refused: {str(e)[:80]}")


def test_transfer(examples):
    V, F = sdm_py.read_mesh(os.path.join(examples, "spot", "spot_triangulated.obj"))
    T = 2.0 * V + np.array([3.0, -1.0, 0.5])  # vertex i of the target is vertex i of the source
    r = sdm_py.transfer(V, F, T, F, size=512)
    faces = r["faces"]
    check(r["face"].shape == (len(T),) and r["barycentric"].shape == (len(T), 3), "a source point per target vertex")
    src = np.einsum("ij,ijk->ik", r["barycentric"], V[F[r["face"]]])
    err = np.linalg.norm(src - V, axis=1) / diagonal(V)
    check(np.mean(err) < 0.005 and np.percentile(err, 90) < 0.01,
          f"Spot onto itself moved and scaled by 2: correspondence error mean {100 * np.mean(err):.3f} %, "
          f"90th percentile {100 * np.percentile(err, 90):.3f} % of the diagonal (< 0.5 %, < 1 %)")
    check(r["atlas"].shape == (512, 512, 4) and r["uv"].shape == (len(faces), 3, 2), "atlas and target uv")


def test_errors(V, F):
    # An open mesh (one face missing) goes through: its skeleton maps every vertex.
    open_skeleton = sdm_py.skeleton(V, F[:-1])
    check(len(open_skeleton["vertex_node"]) == len(V) and open_skeleton["nodes"].shape[0] >= 2,
          f"an open mesh goes through: {open_skeleton['nodes'].shape[0]} nodes, a node for each of its {len(V)} vertices")
    # A fin (a third face on an edge) is non-manifold: refused with the reason.
    fin_V = np.vstack([V, V[F[0, 0]] + 0.5 * np.array([1.0, 1.0, 1.0])])
    fin_F = np.vstack([F, [[F[0, 0], F[0, 1], len(V)]]])
    try:
        sdm_py.skeleton(fin_V, fin_F)
        check(False, "a non-manifold mesh is refused")
    except ValueError as e:
        check("non-manifold" in str(e), f"a non-manifold mesh is refused: {str(e)[:80]}...")


def main():
    examples = sys.argv[1]
    V, F = capsule()
    s = test_skeleton(V, F)
    test_layout(V, F, s)
    with tempfile.TemporaryDirectory() as folder:
        test_maps(V, F, folder)
        test_segment_levels_and_pose(os.path.join(folder, "capsule.exr"))
    test_transfer(examples)
    test_errors(V, F)
    print(f"sdm_py {sdm_py.__version__}: all checks passed")


if __name__ == "__main__":
    main()

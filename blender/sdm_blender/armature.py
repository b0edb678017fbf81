"""Skeletons as Blender armatures and back: an armature with one bone per skeleton edge, and the
posed skeleton (node positions and rotations) an armature's pose stands for. Geometry stays in
sdm_py: these functions only translate between its arrays and Blender's bones."""
import collections

import bpy
import numpy as np


def adjacency(n_nodes, edges):
    """For every node, its (neighbour, edge index) pairs."""
    adjacent = [[] for _ in range(n_nodes)]
    for e, (a, b) in enumerate(edges.tolist()):
        adjacent[a].append((b, e))
        adjacent[b].append((a, e))
    return adjacent


def chains(n_nodes, edges):
    """The skeleton's edges grouped into chains between nodes of degree other than 2 (segments),
    then any cycles of degree-2 nodes: a list of node lists, each with its edge indices."""
    adjacent = adjacency(n_nodes, edges)
    used = np.zeros(len(edges), dtype=bool)
    out = []

    def walk(start, first):
        nodes, ids, node, edge = [start], [], start, first
        while True:
            used[edge] = True
            a, b = edges[edge]
            node = b if a == node else a
            nodes.append(node)
            ids.append(edge)
            nxt = [(m, f) for m, f in adjacent[node] if not used[f]]
            if len(adjacent[node]) != 2 or not nxt:
                return nodes, ids
            edge = nxt[0][1]

    for start in range(n_nodes):
        if len(adjacent[start]) != 2:
            for _, e in adjacent[start]:
                if not used[e]:
                    out.append(walk(start, e))
    for e in range(len(edges)):
        if not used[e]:
            out.append(walk(int(edges[e][0]), e))
    return out


def oriented_edges(nodes, edges, root):
    """(head, tail, edge) of every edge, oriented away from `root` breadth first, then from the
    first node of each other part; a bone's parent is the edge that arrived at its head."""
    adjacent = adjacency(len(nodes), edges)
    arriving, done, out = {}, set(), []
    for start in [root] + list(range(len(nodes))):
        if start in arriving or not adjacent[start]:
            continue
        arriving[start] = None
        queue = collections.deque([start])
        while queue:
            a = queue.popleft()
            for b, e in adjacent[a]:
                if e in done:
                    continue
                done.add(e)
                out.append((a, b, e, arriving[a]))
                if b not in arriving:
                    arriving[b] = e
                    queue.append(b)
    return out


def build(context, name, nodes, edges, root=None):
    """A new armature object (linked to the context's collection) with one bone per edge, named
    segment<chain>.<k>, connected into chains from `root` (default: the node with most edges).
    Its custom property sdm_bones maps every bone to its [head, tail] nodes. Nothing is left behind
    when building fails."""
    if root is None:
        root = int(np.argmax(np.bincount(edges.reshape(-1), minlength=len(nodes))))
    label = {}
    for c, (_, ids) in enumerate(chains(len(nodes), edges)):
        for k, e in enumerate(ids):
            label[e] = f"segment{c}.{k:02d}"
    arm = bpy.data.armatures.new(name)
    new = bpy.data.objects.new(name, arm)
    context.collection.objects.link(new)
    before = context.view_layer.objects.active
    context.view_layer.objects.active = new
    made = False
    try:
        bpy.ops.object.mode_set(mode='EDIT')
        bones, ends = {}, {}
        for a, b, e, parent in oriented_edges(nodes, edges, root):
            bone = arm.edit_bones.new(label[e])
            bone.head, bone.tail = nodes[a], nodes[b]
            if parent is not None:
                bone.parent = bones[parent]
                bone.use_connect = True
            bones[e] = bone
            ends[label[e]] = [int(a), int(b)]
        made = True
    finally:
        if new.mode == 'EDIT':
            bpy.ops.object.mode_set(mode='OBJECT')
        context.view_layer.objects.active = before
        if not made:
            bpy.data.objects.remove(new)
            bpy.data.armatures.remove(arm)
    new["sdm_bones"] = ends
    return new


def posed_skeleton(arm, rest_nodes):
    """The skeleton an armature made by build() stands for in its current pose, in the armature's
    own space: {"nodes": (k, 3), "node_rotations": (k, 4) [x, y, z, w]} for sdm_py.pose. A node's
    rotation is that of the bones leaving it when they agree (else NaN: sdm derives it), for an end
    that of the bone arriving; a node no bone reaches keeps its rest place."""
    nodes = np.array(rest_nodes, dtype=np.float64)
    rotations = np.full((len(nodes), 4), np.nan)
    leaving = collections.defaultdict(list)
    ends = arm["sdm_bones"]
    for pb in arm.pose.bones:
        if pb.name not in ends:
            continue
        a, b = (int(x) for x in ends[pb.name])
        q = (pb.matrix @ pb.bone.matrix_local.inverted()).to_quaternion()
        nodes[a], nodes[b] = pb.head, pb.tail
        leaving[a].append(q)
        if np.isnan(rotations[b, 0]):
            rotations[b] = (q.x, q.y, q.z, q.w)
    for a, qs in leaving.items():
        if all(q.rotation_difference(qs[0]).angle < 1e-6 for q in qs):
            rotations[a] = (qs[0].x, qs[0].y, qs[0].z, qs[0].w)
        else:
            rotations[a] = np.nan
    return {"nodes": nodes, "node_rotations": rotations}

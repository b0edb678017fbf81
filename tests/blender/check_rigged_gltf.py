"""A rigged glTF as Blender's own importer reads it (test_gltf_skin.cpp runs this where Blender is installed):
   blender -b --factory-startup --python-exit-code 1 --python check_rigged_gltf.py -- FILE.glb BONE
imports FILE.glb, turns BONE 90 degrees about the world X axis through its head, and prints one line
`RIGGED-GLTF {json}`: the bones (name, parent, head in glTF's axes: Blender's (x, y, z) is glTF's
(x, z, -y)), the mesh's vertex count, how many vertices have no vertex group, and the largest
distance between a posed vertex and linear blend skinning of the imported weights (BONE's subtree
turned, the rest still), relative to the model's size.
"""
import json
import math
import sys

import bpy
import numpy
from mathutils import Matrix, Vector

# Blender 3.4's glTF importer asks numpy for np.bool, an alias numpy 1.24 removed (Debian bookworm
# ships both): give it back.
if not hasattr(numpy, 'bool'):
    numpy.bool = bool


def main():
    args = sys.argv[sys.argv.index('--') + 1:]
    path, turned = args[0], args[1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    arm = next(o for o in bpy.data.objects if o.type == 'ARMATURE')
    mesh = next(o for o in bpy.data.objects if o.type == 'MESH')
    to_gltf = lambda v: [v.x, v.z, -v.y]
    bones = [{'name': b.name, 'parent': b.parent.name if b.parent else None,
              'head': to_gltf(arm.matrix_world @ b.head_local)} for b in arm.data.bones]
    rest = [mesh.matrix_world @ v.co for v in mesh.data.vertices]
    groups = {g.index: g.name for g in mesh.vertex_groups}
    # the turned bone's subtree follows it
    follows = {turned} | {b.name for b in arm.data.bones[turned].children_recursive}
    head = arm.matrix_world @ arm.data.bones[turned].head_local
    turn = Matrix.Translation(head) @ Matrix.Rotation(math.pi / 2, 4, 'X') @ Matrix.Translation(-head)
    pb = arm.pose.bones[turned]
    pb.matrix = arm.matrix_world.inverted() @ turn @ arm.matrix_world @ pb.bone.matrix_local
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    posed = mesh.evaluated_get(depsgraph).to_mesh()
    size = max((v - rest[0]).length for v in rest)
    worst, ungrouped = 0.0, 0
    for i, v in enumerate(mesh.data.vertices):
        total, expected = 0.0, Vector((0, 0, 0))
        for g in v.groups:
            x = rest[i]
            expected += g.weight * (turn @ x if groups[g.group] in follows else x)
            total += g.weight
        if total == 0:
            ungrouped += 1
            continue
        worst = max(worst, ((mesh.matrix_world @ posed.vertices[i].co) - expected / total).length / size)
    print('RIGGED-GLTF ' + json.dumps({'bones': bones, 'vertices': len(mesh.data.vertices), 'ungrouped': ungrouped,
                                       'pose_error': worst}))


main()

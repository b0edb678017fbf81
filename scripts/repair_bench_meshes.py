#!/usr/bin/python3
"""The meshes of BENCHMARKS "Mesh repair: what it costs", from a clean binary-PLY triangle mesh
(the 449,325-vertex remesh of bunny00: `sdm remesh ../shared/models/cgal/bunny00.off -o
bunny450s.ply --factor 0.3094 --iterations 3`):
  NAME-defects.ply  the same surface with local defects: three tetrahedra that touch it at one
                    vertex each (three non-manifold vertices), two faces repeated, one face flipped;
  NAME-soup.ply     the same surface as a soup: every face with its own three vertices.
Usage: repair_bench_meshes.py CLEAN.ply   (needs numpy)"""
import sys
import numpy as np

FACE = np.dtype([('n', 'u1'), ('i', '<i4', 3)])


def read_ply(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    head = data[:end].decode().split('\n')
    nv = int(next(l for l in head if l.startswith('element vertex')).split()[2])
    nf = int(next(l for l in head if l.startswith('element face')).split()[2])
    if 'property float x' not in head or 'property list uchar int vertex_indices' not in head:
        sys.exit(path + ': expected float x y z and uchar/int faces')
    points = np.frombuffer(data[end:end + nv * 12], dtype='<f4').reshape(-1, 3)
    faces = np.frombuffer(data[end + nv * 12:end + nv * 12 + nf * FACE.itemsize], dtype=FACE)['i']
    return points.copy(), faces.copy()


def write_ply(path, points, faces):
    head = ('ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
            'property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n' % (len(points), len(faces)))
    rec = np.zeros(len(faces), dtype=FACE)
    rec['n'], rec['i'] = 3, faces
    with open(path, 'wb') as f:
        f.write(head.encode() + points.astype('<f4').tobytes() + rec.tobytes())


def with_defects(points, faces):
    diag = np.linalg.norm(points.max(0) - points.min(0))
    P, F, n = [points], [faces], len(points)
    for k, v in enumerate([len(points) // 450, len(points) // 2, (9 * len(points)) // 10]):
        c = points[v] + np.array([0.01, 0.012, 0.008]) * diag * (1 + k)   # a tetrahedron with corner v
        P.append(np.array([c, c + [0.003 * diag, 0, 0], c + [0, 0.003 * diag, 0]], dtype='<f4'))
        a, b, d = n, n + 1, n + 2
        F.append(np.array([[v, b, a], [v, d, b], [v, a, d], [a, b, d]], dtype='<i4'))
        n += 3
    F = np.concatenate(F)
    F = np.concatenate([F, F[[5, len(faces) // 11]]])   # two repeated faces
    k = len(faces) // 7
    F[k] = F[k][[0, 2, 1]]                                # one flipped face
    return np.concatenate(P), F


def soup(points, faces):
    return points[faces.reshape(-1)], np.arange(3 * len(faces), dtype='<i4').reshape(-1, 3)


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    stem = sys.argv[1][:-4] if sys.argv[1].endswith('.ply') else sys.argv[1]
    points, faces = read_ply(sys.argv[1])
    write_ply(stem + '-defects.ply', *with_defects(points, faces))
    write_ply(stem + '-soup.ply', *soup(points, faces))

#!/usr/bin/python3
"""Samples a point cloud from a triangle mesh (OFF), for the point-cloud benchmarks (docs/BENCHMARKS.md,
"Maps of point clouds"): N points uniform by area with a fixed seed, each moved by Gaussian noise of
a given standard deviation (a fraction of the bounding-box diagonal) along every axis; written as
.xyz, with the true normals (`--normals`) or without.

usage: sample_cloud.py MESH.off OUT.xyz [--points 50000] [--noise 0.002] [--normals] [--seed 1]
Convert other formats first: sdm convert MESH -o MESH.off
"""
import argparse

import numpy as np


def read_off(path):
    with open(path) as f:
        words = [w for line in f for w in line.split('#')[0].split()]
    if words[0].upper().endswith('OFF'):
        words = words[1:]
    nv, nf = int(words[0]), int(words[1])
    at = 3
    v = np.array(words[at:at + 3 * nv], dtype=float).reshape(nv, 3)
    at += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(words[at])
        idx = [int(w) for w in words[at + 1:at + 1 + k]]
        at += 1 + k
        faces += [[idx[0], idx[i], idx[i + 1]] for i in range(1, k - 1)]
    return v, np.array(faces, dtype=int)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('mesh')
    ap.add_argument('out')
    ap.add_argument('--points', type=int, default=50000)
    ap.add_argument('--noise', type=float, default=0.002)
    ap.add_argument('--normals', action='store_true')
    ap.add_argument('--seed', type=int, default=1)
    a = ap.parse_args()
    v, f = read_off(a.mesh)
    rng = np.random.default_rng(a.seed)
    p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(p1 - p0, p2 - p0)
    area = np.linalg.norm(cross, axis=1)
    tri = rng.choice(len(f), size=a.points, p=area / area.sum())
    r1, r2 = rng.random(a.points), rng.random(a.points)
    s = np.sqrt(r1)
    pts = (1 - s)[:, None] * p0[tri] + (s * (1 - r2))[:, None] * p1[tri] + (s * r2)[:, None] * p2[tri]
    diag = np.linalg.norm(v.max(axis=0) - v.min(axis=0))
    pts += rng.normal(scale=a.noise * diag, size=pts.shape)
    with open(a.out, 'w') as out:
        if a.normals:
            n = cross[tri] / np.maximum(area[tri], 1e-300)[:, None]
            np.savetxt(out, np.hstack([pts, n]), fmt='%.9g')
        else:
            np.savetxt(out, pts, fmt='%.9g')


if __name__ == '__main__':
    main()

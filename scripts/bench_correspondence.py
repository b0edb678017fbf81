#!/usr/bin/python3
"""Correspondence benchmark of `sdm transfer` (or `sdm correspond`) on data with its own ground truth.

Runs every ordered pair of humans_r (FAUST_r 014, 026, 038), the TOSCA_r pairs centaur0 <-> centaur3
and david6 <-> david12, and the SHREC'19 pairs with gt_pairs among shapes 01, 16 and 44, and prints
per pair:
  - the error: geodesic distance on the source between assigned and true point / sqrt(source area)
    x 100 (Kim et al. 2011), mean and 90th percentile, judged by the independent checker
    (judge/scripts/corr_error_gt.py, 1000 sampled ground-truth points);
  - the orientation: the share of the same sampled points whose assigned point lies geodesically
    nearer the mirror of the true point than the true point (a left/right or front/back flip shows
    as about 50 % or more; a right map a few % from points near the plane of symmetry). The mirror
    comes from NAME.sym.vts (FAUST_r, TOSCA_r); SHREC'19 has none, so its mirror is derived: the
    shapes' SMPL correspondences (smpl_corres/) and a SMPL left/right map built from the FAUST_r
    mirrors (FAUST registrations share SMPL's vertex order; sampleID.vts gives each FAUST_r point's
    registration vertex). Points without a mirror are left out; "n/a" where no mirror exists.

Usage: scripts/bench_correspondence.py [--sdm build/sdm] [--models ../shared/models]
           [--judge ../shared/judge/scripts] [--work DIR] [--only SUBSTRING] [--command transfer|correspond]
           [--json] [-- EXTRA SDM ARGS]
The source goes to `sdm transfer` as a PLY with float coordinates and grey vertex colours, to `sdm
correspond` as its OFF file: the last bits of the coordinates differ, and so may the skeletons (compare
runs of one command).
Exit 0 when every pair ran (refusals are reported as rows), 2 for a missing input.
"""
import json, os, re, subprocess, sys, tempfile, time
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def read_off(p):
    L = [l for l in open(p).read().split('\n') if l.strip() and not l.startswith('#')]
    i = 1 if L[0].strip().upper() == 'OFF' else 0
    nv, nf = map(int, L[i].split()[:2])
    V = np.array([list(map(float, l.split()[:3])) for l in L[i + 1:i + 1 + nv]])
    F = np.array([list(map(int, l.split()[1:4])) for l in L[i + 1 + nv:i + 1 + nv + nf]])
    return V, F


def write_colored_ply(V, F, path):
    """The source as a PLY with a grey colour per vertex: `sdm transfer` needs a texture or colours."""
    with open(path, 'w') as f:
        f.write('ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
                'property uchar red\nproperty uchar green\nproperty uchar blue\nelement face %d\n'
                'property list uchar int vertex_indices\nend_header\n' % (len(V), len(F)))
        for v in V: f.write('%.9g %.9g %.9g 128 128 128\n' % tuple(v))
        for t in F: f.write('3 %d %d %d\n' % tuple(t))


def pairs(models):
    """(name, source .off, target .off, ground truth): ('vts', source.vts, target.vts, source.sym.vts)
    or ('pairs', TARGET_SOURCE.txt, source name)."""
    out = []
    h = os.path.join(models, 'humans_r')
    names = ['tr_reg_014', 'tr_reg_026', 'tr_reg_038']
    for a in names:
        for b in names:
            if a != b:
                out.append(('faust_r %s->%s' % (a[-3:], b[-3:]), '%s/%s.off' % (h, a), '%s/%s.off' % (h, b),
                            ('vts', '%s/corres/%s.vts' % (h, a), '%s/corres/%s.vts' % (h, b), '%s/corres/%s.sym.vts' % (h, a))))
    t = os.path.join(models, 'tosca_r')
    for a, b in [('centaur0', 'centaur3'), ('centaur3', 'centaur0'), ('david6', 'david12'), ('david12', 'david6')]:
        out.append(('tosca_r %s->%s' % (a, b), '%s/%s.off' % (t, a), '%s/%s.off' % (t, b),
                    ('vts', '%s/corres/%s.vts' % (t, a), '%s/corres/%s.vts' % (t, b), '%s/corres/%s.sym.vts' % (t, a))))
    s = os.path.join(models, 'shrec19')
    ids = ['01', '16', '44']
    for a in ids:  # gt_pairs/T_S.txt: per vertex of T (the target), its vertex of S (the source)
        for b in ids:
            f = '%s/gt_pairs/%d_%d.txt' % (s, int(b), int(a))
            if a != b and os.path.exists(f):
                out.append(('shrec19 %s->%s' % (a, b), '%s/shape_%s.off' % (s, a), '%s/shape_%s.off' % (s, b), ('pairs', f, 'shape_' + a)))
    return out


def smpl_mirror(models):
    """Per SMPL (FAUST registration) vertex, its left/right mirror vertex, or -1: from the FAUST_r
    mirrors (NAME.sym.vts) and sampleID.vts."""
    c = os.path.join(models, 'humans_r', 'corres')
    sid = np.loadtxt(c + '/sampleID.vts', dtype=int) - 1
    m = -np.ones(6890, dtype=int)
    for n in ['tr_reg_014', 'tr_reg_026', 'tr_reg_038']:
        v = np.loadtxt('%s/%s.vts' % (c, n), dtype=int) - 1
        sym = np.loadtxt('%s/%s.sym.vts' % (c, n), dtype=int) - 1
        line_of = {}
        for k, x in enumerate(v): line_of.setdefault(x, k)
        for k, x in enumerate(sym):
            if m[sid[k]] < 0 and x in line_of: m[sid[k]] = sid[line_of[x]]
    return m


def shrec_mirror(models, shape, n_vertices, smpl_m):
    """Per vertex of a SHREC'19 shape, its mirror vertex (or -1) through the SMPL correspondence."""
    corr = np.loadtxt('%s/shrec19/smpl_corres/%s.smpl.vts' % (models, shape), dtype=int) - 1
    m = -np.ones(n_vertices, dtype=int)
    for i, x in enumerate(corr):
        if m[x] < 0 and smpl_m[i] >= 0: m[x] = corr[smpl_m[i]]
    return m


def orientation(judge, Vs, Fs, C, sv, tv, mirror):
    """Share (%) of the judge's 1000 sampled points (same seed) whose assigned point is geodesically
    nearer the true point's mirror than the true point; points without a mirror left out. Distances
    from the corner of the assigned point's face nearest it, in the judge's Steiner graph with one
    point per edge (which of two places is nearer needs no more)."""
    sys.path.insert(0, judge)
    from geodesic import SteinerGraph
    from scipy.sparse.csgraph import dijkstra
    k = np.random.default_rng(7).choice(len(tv), size=min(1000, len(tv)), replace=False)
    k = k[mirror[sv[k]] >= 0]
    fi = C[:, 0].astype(int); w = C[:, 1:4]
    corner = Fs[fi[tv[k]], np.argmax(w[tv[k]], axis=1)]
    g = SteinerGraph(Vs, Fs, 1)
    nearer = 0
    for c in range(0, len(k), 64):
        D = dijkstra(g.G, indices=corner[c:c + 64])
        r = np.arange(len(D))
        nearer += int((D[r, mirror[sv[k[c:c + 64]]]] < D[r, sv[k[c:c + 64]]]).sum())
    return float(nearer / max(len(k), 1) * 100), int(len(k))


def run_pair(args, work, name, src, tgt, gt, smpl_m):
    row = {'pair': name}
    corr = os.path.join(work, name.replace(' ', '_').replace('>', '') + '.txt')
    if args['command'] == 'correspond':
        cmd = [args['sdm'], 'correspond', src, tgt, '-o', corr, '--json'] + args['extra']
    else:
        Vs, Fs = read_off(src)
        ply = os.path.join(work, os.path.basename(src)[:-4] + '_grey.ply')
        if not os.path.exists(ply): write_colored_ply(Vs, Fs, ply)
        cmd = [args['sdm'], 'transfer', '--source', ply, '--target', tgt, '-o', os.path.join(work, 'out.obj'), '--size', '256',
               '--correspondence', corr] + args['extra']
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    row['seconds'] = round(time.time() - t0, 1)
    with open(corr[:-4] + '.log', 'w') as f: f.write(p.stderr + p.stdout)
    if p.returncode != 0:
        lines = [l for l in p.stderr.strip().split('\n') if l.strip()]
        row['refused'] = 'exit %d: %s' % (p.returncode, lines[-1][:300] if lines else '')
        return row
    if args['command'] == 'correspond':
        try:
            j = json.loads(p.stdout)
            row['kind'] = j.get('kind')
            for k in ['final_score', 'rival_score', 'rival_kept', 'ambiguity']: row[k] = j.get(k)
        except ValueError:
            pass
    warnings = [l for l in p.stderr.split('\n') if 'warning' in l]
    if warnings: row['warnings'] = warnings
    if gt[0] == 'vts':
        jarg = ['--vts', gt[1], gt[2]]
    else:
        jarg = ['--pairs', gt[1]]
    j = subprocess.run(['/usr/bin/python3', os.path.join(args['judge'], 'corr_error_gt.py'), src, tgt, corr] + jarg,
                       capture_output=True, text=True)
    if j.returncode != 0:
        row['refused'] = 'judge: ' + j.stderr.strip()[-300:]
        return row
    row.update(json.loads(j.stdout))
    Vs, Fs = read_off(src)
    C = np.loadtxt(corr, comments='#')
    if gt[0] == 'vts':
        sv = np.loadtxt(gt[1], dtype=int) - 1; tv = np.loadtxt(gt[2], dtype=int) - 1
        sym = np.loadtxt(gt[3], dtype=int) - 1
        mirror = -np.ones(len(Vs), dtype=int)
        mirror[sv] = sym  # line k: the source's true point and its mirror
    else:
        sv = np.loadtxt(gt[1], dtype=int) - 1; tv = np.arange(len(sv))
        mirror = shrec_mirror(args['models'], gt[2], len(Vs), smpl_m)
    row['nearer_mirror%'], row['mirror_samples'] = orientation(args['judge'], Vs, Fs, C, sv, tv, mirror)
    row['nearer_mirror%'] = round(row['nearer_mirror%'], 2)
    return row


def main():
    a = sys.argv[1:]
    extra = []
    if '--' in a: k = a.index('--'); extra = a[k + 1:]; a = a[:k]
    opt = {'sdm': os.path.join(REPO, 'build', 'sdm'), 'models': os.path.join(REPO, '..', 'shared', 'models'),
           'judge': os.path.join(REPO, '..', 'shared', 'judge', 'scripts'), 'work': None, 'only': '', 'command': ''}
    js = '--json' in a
    a = [x for x in a if x != '--json']
    for i in range(0, len(a), 2):
        key = a[i].lstrip('-')
        if key not in opt or i + 1 >= len(a): sys.exit(__doc__)
        opt[key] = a[i + 1]
    for k in ['sdm', 'models', 'judge']:
        if not os.path.exists(opt[k]):
            print('bench_correspondence: %s not found (--%s)' % (opt[k], k), file=sys.stderr)
            sys.exit(2)
    listing = subprocess.run([opt['sdm'], '--help'], capture_output=True, text=True).stdout
    has_correspond = re.search(r'^\s+correspond\s', listing, re.M) is not None
    if opt['command'] not in ('', 'transfer', 'correspond'): sys.exit(__doc__)
    opt['command'] = opt['command'] or ('correspond' if has_correspond else 'transfer')
    opt['extra'] = extra
    work = opt['work'] or tempfile.mkdtemp(prefix='bench_corr_')
    os.makedirs(work, exist_ok=True)
    smpl_m = smpl_mirror(opt['models'])
    rows = []
    print('| pair | geodesic mean | geodesic p90 | nearer mirror (%) | s | note |\n|---|---|---|---|---|---|', flush=True)
    for name, src, tgt, gt in pairs(opt['models']):
        if opt['only'] and opt['only'] not in name: continue
        r = run_pair(opt, work, name, src, tgt, gt, smpl_m)
        rows.append(r)
        if 'refused' in r:
            print('| %s | - | - | - | %s | %s |' % (name, r['seconds'], r['refused']), flush=True)
        else:
            note = '; '.join(r.get('warnings', []))[:200]
            if r.get('final_score') is not None:
                note = '%s, full fits %.4g (kept) / %.4g (rival)%s; ' % (r['kind'], r['final_score'], r['rival_score'] or float('nan'),
                                                                     ', rival kept' if r.get('rival_kept') else '') + note
            print('| %s | %.2f | %.2f | %.1f (of %d) | %s | %s |' % (name, r['geo_mean'], r['geo_p90'], r['nearer_mirror%'],
                                                                 r['mirror_samples'], r['seconds'], note), flush=True)
    if js: print(json.dumps({'command': opt['command'], 'pairs': rows}))


if __name__ == '__main__':
    main()

"""Tests of `sdm batch` (python/sdm_batch.py; run by CTest as python.batch): the shared models and
two broken files on a local cluster of two workers; the summary, the outputs, the resume.

Usage: test_sdm_batch.py SDM_BINARY EXAMPLES_DATA [SHARED_MODELS]
"""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

SDM = sys.argv[1] if len(sys.argv) > 1 else ''
EXAMPLES = sys.argv[2] if len(sys.argv) > 2 else ''
SHARED = sys.argv[3] if len(sys.argv) > 3 else ''
failures = []


def check(ok, what):
    print(('ok   ' if ok else 'FAIL ') + what)
    if not ok:
        failures.append(what)


def batch(*args):
    p = subprocess.run([SDM, 'batch'] + list(args), capture_output=True, text=True, timeout=900)
    return p.returncode, p.stdout, p.stderr


def rows_of(out):
    with open(os.path.join(out, 'summary.csv')) as f:
        return {r['name']: r for r in csv.DictReader(f)}


def main():
    """The checks; under a __main__ guard, since Dask's local workers start by importing this file."""
    with tempfile.TemporaryDirectory() as tmp:
        models = os.path.join(tmp, 'models')
        os.makedirs(models)
        good = [os.path.join(EXAMPLES, 'spot', 'spot_triangulated.obj')]
        wild = os.path.join(SHARED, 'wild') if SHARED else ''
        if wild and os.path.isdir(wild):
            good += [os.path.join(wild, m) for m in ('cow.obj', 'suzanne.obj', 'teapot.obj', 'beetle.obj')]
        else:
            print('note: %s missing: the batch runs on the bundled Spot alone' % (wild or 'SHARED_MODELS'))
        for m in good:
            os.symlink(m, os.path.join(models, os.path.basename(m)))
        with open(os.path.join(models, 'empty.obj'), 'w'):
            pass
        with open(os.path.join(models, 'truncated.off'), 'w') as f:
            f.write('OFF\n400 2 0\n0 0 0\n1 0 0\n')
        names = [os.path.splitext(os.path.basename(m))[0] for m in good]
        out = os.path.join(tmp, 'out')

        # A first run: every good model through stm and encode, the broken ones recorded.
        start = time.monotonic()
        code, stdout, stderr = batch(models, '-o', out, '--do', 'stm,encode', '--workers', '2')
        first = time.monotonic() - start
        print(stdout + stderr)
        check(code == 1, 'a batch with failures exits 1 (got %d)' % code)
        rows = rows_of(out)
        check(len(rows) == len(good) + 2, 'one row per model: %d for %d' % (len(rows), len(good) + 2))
        check('] %d/%d ' % (len(good) + 2, len(good) + 2) in stderr, 'a progress bar on stderr to the last model')
        summary = json.load(open(os.path.join(out, 'summary.json')))
        check(summary['models'] == len(good) + 2 and summary['ok'] == len(good), 'summary.json counts %d models, %d ok' % (summary['models'], summary['ok']))
        for n in names:
            r = rows.get(n, {})
            check(r.get('status') == 'ok' and r.get('exit_code') == '0', '%s: ok (%s)' % (n, r.get('error')))
            layout = os.path.join(out, n, n + '.layout.json')
            exr = os.path.join(out, n, n + '.exr')
            check(os.path.isfile(exr) and os.path.getsize(exr) > 10000, '%s: its map written' % n)
            segments = len(json.load(open(layout))['segments']) if os.path.isfile(layout) else 0
            check(segments > 0, '%s: its layout written (%d segments)' % (n, segments))
            check(float(r.get('stm_coverage') or 0) >= 0.9, '%s: atlas coverage %s >= 0.9' % (n, r.get('stm_coverage')))
            check(float(r.get('encode_carried') or 0) >= 0.9, '%s: the map carries %s of the surface' % (n, r.get('encode_carried')))
        # The figures are the commands' own: the same stm run by hand gives the same coverage.
        direct = subprocess.run([SDM, 'stm', good[0], '-o', os.path.join(tmp, 'direct.json'), '--json'], capture_output=True, text=True)
        coverage = json.loads(direct.stdout[direct.stdout.find('{'):])['coverage']
        check(abs(coverage - float(rows[names[0]]['stm_coverage'])) < 1e-12, 'coverage as sdm stm prints it: %s' % coverage)
        for n, words in (('empty', 'the file is empty'), ('truncated', 'truncated')):
            r = rows.get(n, {})
            check(r.get('status') == 'failed' and r.get('exit_code') == '2' and words in r.get('error', ''),
                  '%s: failed with exit code 2 and its reason (%s)' % (n, r.get('error')))
            check(not os.path.exists(os.path.join(out, n)), '%s: nothing left behind' % n)

        # The resume: the finished models are skipped, their outputs untouched; the broken ones are tried again.
        exr = os.path.join(out, names[0], names[0] + '.exr')
        stamp = os.path.getmtime(exr)
        start = time.monotonic()
        code, stdout, stderr = batch(models, '-o', out, '--do', 'stm,encode')
        again = time.monotonic() - start
        rows = rows_of(out)
        check(all(rows[n]['status'] == 'skipped (done before)' for n in names), 'a second run skips every finished model')
        check(os.path.getmtime(exr) == stamp, 'and leaves its outputs as they were')
        check(rows['empty']['status'] == 'failed', 'a broken model is tried again and fails again')
        print('first run %.1f s, resumed run %.1f s' % (first, again))
        check(again < first, 'the resumed run is the shorter (%.1f s against %.1f s)' % (again, first))
        # An output gone: that model runs again, the others stay skipped.
        os.remove(exr)
        code, stdout, stderr = batch(models, '-o', out, '--do', 'stm,encode')
        rows = rows_of(out)
        check(rows[names[0]]['status'] == 'ok' and os.path.isfile(exr), '%s: done again once its map was removed' % names[0])
        check(all(rows[n]['status'] == 'skipped (done before)' for n in names[1:]), 'the other models stay skipped')
        # Other steps are other work: --do stm alone does not count the stm,encode runs as done.
        code, stdout, stderr = batch(good[0], '-o', out, '--do', 'stm')
        check(code == 0 and rows_of(out)[names[0]]['status'] == 'ok', 'other steps run anew (exit %d)' % code)

        # The time limit: a model over it is killed and recorded.
        code, stdout, stderr = batch(good[0], '-o', os.path.join(tmp, 'slow'), '--do', 'encode', '--timeout', '0.5')
        r = rows_of(os.path.join(tmp, 'slow'))[names[0]]
        check(code == 1 and r['status'] == 'timeout' and '--timeout' in r['error'], 'a model over --timeout is killed and recorded (%s)' % r['status'])
        # Bad arguments: exit 2, a message, nothing written.
        code, stdout, stderr = batch(good[0], '-o', os.path.join(tmp, 'bad'), '--do', 'stm,colour')
        check(code == 2 and "unknown step 'colour'" in stderr and not os.path.exists(os.path.join(tmp, 'bad')),
              'an unknown step: exit 2 naming it, nothing written')
        code, stdout, stderr = batch(os.path.join(tmp, 'missing.obj'), '-o', os.path.join(tmp, 'bad'))
        check(code == 2 and 'no such file' in stderr, 'a missing input: exit 2 naming it')

        # From Python, the same batch.
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(SDM)), 'python'))
        import sdm_batch
        rows = sdm_batch.run_batch([good[0]], os.path.join(tmp, 'py'), 'stm', sdm=SDM, workers=1, progress=False)
        check(len(rows) == 1 and rows[0]['status'] == 'ok' and abs(rows[0]['stm_coverage'] - coverage) < 1e-12,
              'sdm_batch.run_batch from Python: the same row')
    print('%d failure(s)' % len(failures))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()

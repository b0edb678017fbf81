"""Tests of `sdm batch` (python/sdm_batch.py; run by CTest as python.batch): the shared models and
two broken files on a local cluster of two workers; the summary, the outputs, the resume; models
named alike, a model changed under its name, a name that is not UTF-8; bad output folders, limits,
a full disk and Ctrl-C, each a sentence and an exit code, no traceback and no temporary file.

Usage: test_sdm_batch.py SDM_BINARY EXAMPLES_DATA [SHARED_MODELS]
"""
import csv
import hashlib
import json
import os
import shutil
import signal
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


def batch(*args, env=None):
    p = subprocess.run([SDM, 'batch'] + list(args), capture_output=True, text=True, errors='replace', timeout=900, env=env)
    return p.returncode, p.stdout, p.stderr


def rows_of(out):
    with open(os.path.join(out, 'summary.csv'), encoding='utf-8') as f:
        return {r['name']: r for r in csv.DictReader(f)}


def leftovers(folder):
    """Temporary files under `folder`: sdm's (.NAME.tmpPID.EXT), the batch's (.NAME.tmp) and its marker."""
    return [os.path.join(d, f) for d, _, files in os.walk(folder) for f in files if '.tmp' in f or f.startswith('.batch-running')]


def coverage_of(model, tmp):
    """The atlas coverage `sdm stm` prints for `model`, run by hand."""
    p = subprocess.run([SDM, 'stm', model, '-o', os.path.join(tmp, 'direct.json'), '--json'], capture_output=True, text=True)
    return json.loads(p.stdout[p.stdout.find('{'):])['coverage']


def primitive(name, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    subprocess.run([SDM, 'primitive', name, '-o', path], check=True, capture_output=True)


def sha256(path):
    return hashlib.sha256(open(path, 'rb').read()).hexdigest()


def clean_failure(code, stderr, want_code, words, what):
    check(code == want_code and words in stderr and 'Traceback' not in stderr,
          '%s: exit %d and a sentence naming it (exit %d: %s)' % (what, want_code, code, stderr.strip()[-300:]))


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
        check(not leftovers(os.path.join(tmp, 'slow')), 'and leaves no temporary file: %s' % leftovers(os.path.join(tmp, 'slow')))
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
    with tempfile.TemporaryDirectory() as tmp:
        names_and_content(tmp)
        bad_outputs_and_limits(tmp)
        interrupted(tmp)
        full_disk(tmp)
    print('%d failure(s)' % len(failures))
    sys.exit(1 if failures else 0)


def names_and_content(tmp):
    """a/sp.obj, b/sp.obj and sp-2.obj get folders of their own and rows with their own figures; a
    name that is not UTF-8 runs like any other; a model changed under its name (its modification
    time put back) runs again, the others stay skipped."""
    m = os.path.join(tmp, 'alike')
    models = {'a_sp': os.path.join(m, 'a', 'sp.obj'), 'b_sp': os.path.join(m, 'b', 'sp.obj'), 'sp-2': os.path.join(m, 'sp-2.obj'),
              'caf_': os.path.join(os.fsencode(m), b'caf\xe9.obj').decode('utf-8', 'surrogateescape')}
    for (name, path), shape in zip(models.items(), ('capsule', 'ypsilon', 'bottle', 'mushroom')):
        primitive(shape, path)
    out = os.path.join(tmp, 'alike-out')
    # The folder adds sp-2.obj again (run once) and the non-UTF-8 name.
    code, stdout, stderr = batch(models['a_sp'], models['b_sp'], models['sp-2'], m, '-o', out, '--do', 'stm')
    print(stdout + stderr)
    check(code == 0 and 'Traceback' not in stderr, 'models named alike and a non-UTF-8 name: exit 0 (got %d)' % code)
    rows = rows_of(out)
    check(sorted(rows) == sorted(models), 'a folder per model: %s' % sorted(rows))
    for name, path in models.items():
        r = rows.get(name, {})
        want = coverage_of(path, tmp)
        check(r.get('status') == 'ok' and abs(float(r.get('stm_coverage') or -1) - want) < 1e-12,
              '%s: its own coverage %s (by hand %s)' % (name, r.get('stm_coverage'), want))
        check(r.get('input_sha256') == sha256(path), '%s: the row names its own content' % name)
        check(os.path.isfile(os.path.join(out, name, name + '.layout.json')), '%s: its layout in its own folder' % name)
    # A new mesh under an old name, with the old modification time: done again, the others skipped.
    stamp = os.stat(models['a_sp']).st_mtime_ns
    shutil.copyfile(models['sp-2'], models['a_sp'])
    os.utime(models['a_sp'], ns=(stamp, stamp))
    code, stdout, stderr = batch(models['a_sp'], models['b_sp'], models['sp-2'], m, '-o', out, '--do', 'stm')
    rows = rows_of(out)
    want = coverage_of(models['a_sp'], tmp)
    check(rows['a_sp']['status'] == 'ok' and abs(float(rows['a_sp']['stm_coverage']) - want) < 1e-12,
          'a model changed under its name runs again: %s, coverage %s (by hand %s)' % (rows['a_sp']['status'], rows['a_sp']['stm_coverage'], want))
    check(all(rows[n]['status'] == 'skipped (done before)' for n in ('b_sp', 'sp-2', 'caf_')), 'the unchanged ones are skipped')
    check(not leftovers(out), 'no temporary file left: %s' % leftovers(out))


def bad_outputs_and_limits(tmp):
    """An output that is a file, a folder that cannot be written and out-of-range numbers: exit 2
    and a sentence, nothing written."""
    model = os.path.join(tmp, 'alike', 'sp-2.obj')
    afile = os.path.join(tmp, 'a-file')
    open(afile, 'w').close()
    code, stdout, stderr = batch(model, '-o', afile)
    clean_failure(code, stderr, 2, 'it is a file, not a folder', '-o naming a file')
    for option, value, words in (('--timeout', 'nan', '--timeout nan'), ('--timeout', '-3', '--timeout'), ('--timeout', 'inf', '--timeout inf'),
                                 ('--workers', '0', '--workers 0'), ('--max-memory', '1.2.3', "--max-memory '1.2.3'"),
                                 ('--max-memory', '0', "--max-memory '0'")):
        code, stdout, stderr = batch(model, '-o', os.path.join(tmp, 'limits'), option, value)
        clean_failure(code, stderr, 2, words, '%s %s' % (option, value))
    check(not os.path.exists(os.path.join(tmp, 'limits')), 'nothing written for bad limits')
    # A read-only folder: a read-only mount for root (who writes through permissions), else permissions.
    ro = os.path.join(tmp, 'read-only')
    os.makedirs(ro)
    mounted = os.geteuid() == 0 and subprocess.run(['mount', '-t', 'tmpfs', '-o', 'ro,size=64k', 'tmpfs', ro], capture_output=True).returncode == 0
    if os.geteuid() == 0 and not mounted:
        print('skip: a read-only folder needs a mount (not permitted here) when running as root')
        return
    if not mounted:
        os.chmod(ro, 0o555)
    try:
        for out in (ro, os.path.join(ro, 'sub')):
            code, stdout, stderr = batch(model, '-o', out)
            clean_failure(code, stderr, 2, 'cannot write there', '-o %s in a read-only folder' % os.path.relpath(out, tmp))
    finally:
        if mounted:
            subprocess.run(['umount', ro])


def interrupted(tmp):
    """Ctrl-C (SIGINT to the batch's process group, as a terminal sends it) while a command has
    written its temporary map: exit 130, one sentence, the command stopped, no temporary file."""
    model = os.path.join(tmp, 'alike', 'sp-2.obj')
    out = os.path.join(tmp, 'interrupted')
    env = dict(os.environ, SDM_TEST_PAUSE_AFTER_WRITE='.exr')  # the command stops once its map is written
    p = subprocess.Popen([SDM, 'batch', model, '-o', out, '--do', 'encode', '--workers', '1'], env=env, start_new_session=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors='replace')
    deadline = time.monotonic() + 300
    while not leftovers(os.path.join(out, 'sp-2')) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.1)
    had = leftovers(os.path.join(out, 'sp-2'))
    os.killpg(p.pid, signal.SIGINT)
    stdout, stderr = p.communicate(timeout=120)
    print(stderr)
    check(bool(had), 'the command had its temporary map when interrupted: %s' % had)
    clean_failure(p.returncode, stderr, 130, 'interrupted (SIGINT)', 'Ctrl-C')
    check(not leftovers(out), 'no temporary file after Ctrl-C: %s' % leftovers(out))
    running = [pid for pid in os.listdir('/proc') if pid.isdigit() and out.encode() in open_cmdline(pid)]
    check(not running, 'no command left running: %s' % running)


def open_cmdline(pid):
    try:
        with open('/proc/%s/cmdline' % pid, 'rb') as f:
            return f.read()
    except OSError:
        return b''


def full_disk(tmp):
    """A disk that fills up (a 1 MB tmpfs, root only): the summary cannot be written (exit 1, a
    sentence, the old summary kept, no .tmp); a model whose record cannot be written stays ok."""
    disk = os.path.join(tmp, 'disk')
    os.makedirs(disk)
    if os.geteuid() != 0 or subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=1m', 'tmpfs', disk], capture_output=True).returncode != 0:
        print('skip: a full disk needs a tmpfs mount (root; not permitted here)')
        return
    try:
        model = os.path.join(tmp, 'alike', 'sp-2.obj')
        out = os.path.join(disk, 'out')
        code, stdout, stderr = batch(model, '-o', out, '--do', 'stm')
        check(code == 0, 'the batch fits the disk (exit %d)' % code)
        before = open(os.path.join(out, 'summary.csv'), 'rb').read()
        try:
            with open(os.path.join(disk, 'filler'), 'wb', buffering=0) as f:
                while True:
                    f.write(b'\0' * 4096)
        except OSError:  # full
            pass
        code, stdout, stderr = batch(model, '-o', out, '--do', 'stm')
        clean_failure(code, stderr, 1, 'cannot write the summary', 'a full disk at the summary')
        check('skipped (done before)' in stdout, 'the table still printed, the model skipped')
        check(open(os.path.join(out, 'summary.csv'), 'rb').read() == before, 'the old summary kept whole')
        # roundtrip writes no output: a model new to the folder finishes, its record does not fit.
        fresh = os.path.join(tmp, 'fresh.obj')
        shutil.copyfile(model, fresh)
        code, stdout, stderr = batch(fresh, '-o', out, '--do', 'roundtrip')
        print(stdout + stderr)
        row = [l for l in stdout.splitlines() if l.startswith('| fresh |')]
        check(code == 1 and row and '| ok |' in row[0] and 'could not be written' in row[0] and 'Traceback' not in stderr,
              'a finished model whose record does not fit stays ok, saying so: %s' % row)
        check(not leftovers(disk), 'no temporary file on the full disk: %s' % leftovers(disk))
    finally:
        subprocess.run(['umount', disk])


if __name__ == '__main__':
    main()

#!/usr/bin/python3
"""sdm batch: the sdm commands over a folder or a manifest of models, each model a task on Dask.

Every model runs as its own task on a Dask cluster (Debian's python3-distributed): a local one of
--workers processes by default, or the scheduler at --scheduler ADDRESS. A task runs the `sdm`
commands of --do for its model, one after the other, as child processes, under a time limit
(--timeout, the task's wall time) and a memory limit (--max-memory, the resident memory of the
command running; also passed to each command's own --max-memory check), so that a model that
hangs, crashes or swells is recorded and the batch goes on. Outputs go to OUTDIR/NAME/ (NAME: the
model's file name without its extension; where two models share it, their paths relative to the
models' common folder, a/sp.obj -> a_sp; still equal names get -2, -3 in the order of the paths). A
task that finishes writes OUTDIR/NAME/batch.json last, with the size and SHA-256 of its model (and
of a transfer's source), and a later run skips every model whose batch.json says it finished the
same steps on the same content and whose outputs are all there; a model whose file changed runs
again. At the end: OUTDIR/summary.csv and OUTDIR/summary.json, one row per model (status, exit
code, error, seconds, the commands' figures); with --report also OUTDIR/report.html, one
self-contained page to look at them: a row per model with its pictures, sortable by any column.

Steps (--do, comma-separated, in this order for each model):
  skeleton            sdm skeleton MODEL -o NAME.skeleton.json
  stm                 sdm stm MODEL -o NAME.layout.json          (figure: coverage)
  encode              sdm encode MODEL -o NAME.exr               (figures: base faces, carried)
  roundtrip           sdm roundtrip MODEL                        (figures: rms, hausdorff)
  transfer:SOURCE     sdm transfer --source SOURCE --target MODEL -o NAME.transfer.obj

From Python: `import sdm_batch; rows = sdm_batch.run_batch(["a.obj", "b.off"], "out", "stm")`, in a
script under `if __name__ == "__main__":` (the local cluster's workers start by importing it).
Exit codes: 0 when every model finished, 1 when some failed (the table says which) or the summary
could not be written (a full disk), 2 for bad arguments (a missing input, an unknown step, an
output folder that is a file or not writable, a --timeout that is no positive number, no Dask),
130 for Ctrl-C and 143 for SIGTERM: the running commands are stopped (they remove their temporary
files), the finished models keep their outputs and batch.json, a rerun resumes.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time

MESH_EXTENSIONS = ('.obj', '.off', '.ply', '.stl', '.glb', '.gltf')
STATUS_OK, STATUS_SKIPPED = 'ok', 'skipped (done before)'


class BatchError(Exception):
    """Bad arguments: the message names the problem; exit code 2."""


class BatchFailure(Exception):
    """The batch could not finish its work (the summary not written): the message says why; exit code 1."""


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM reached the batch (main's handlers raise it): exit code 128 + the signal."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def shown(path):
    """A path as text that prints and encodes anywhere: bytes that are not UTF-8 become U+FFFD."""
    return path.encode('utf-8', 'surrogateescape').decode('utf-8', 'replace')


# ---- what to run -------------------------------------------------------------------------------

def parse_steps(text):
    """The --do list as (step, argument) pairs; raises BatchError for an unknown step."""
    steps = []
    for word in [w.strip() for w in text.split(',') if w.strip()]:
        name, _, arg = word.partition(':')
        if name not in ('skeleton', 'stm', 'encode', 'roundtrip', 'transfer'):
            raise BatchError("unknown step '%s' in --do (use skeleton, stm, encode, roundtrip, transfer:SOURCE)" % word)
        if name == 'transfer' and not arg:
            raise BatchError("--do transfer needs its source model: transfer:SOURCE")
        if name == 'transfer' and not os.path.isfile(arg):
            raise BatchError("--do %s: the source model %s does not exist" % (word, arg))
        steps.append((name, os.path.abspath(arg) if arg else ''))
    if not steps:
        raise BatchError('--do names no step')
    return steps


def find_models(inputs):
    """The models named by `inputs`: mesh files, folders (their mesh files, not recursing) and
    manifests (.txt: one path a line, relative to the manifest's folder, '#' comments)."""
    models = []
    for item in inputs:
        try:
            if os.path.isdir(item):
                models += sorted(os.path.join(item, f) for f in os.listdir(item) if f.lower().endswith(MESH_EXTENSIONS))
            elif item.lower().endswith('.txt') and os.path.isfile(item):
                base = os.path.dirname(os.path.abspath(item))
                with open(item, encoding='utf-8', errors='surrogateescape') as f:
                    for line in f:
                        line = line.split('#', 1)[0].strip()
                        if line:
                            models.append(line if os.path.isabs(line) else os.path.join(base, line))
            elif os.path.exists(item):
                models.append(item)
            else:
                raise BatchError('%s: no such file or folder' % shown(item))
        except OSError as e:
            raise BatchError('cannot read %s: %s' % (shown(item), e.strerror or e))
    if not models:
        raise BatchError('no models found in %s (mesh files: %s)' % (shown(' '.join(inputs)), ' '.join(MESH_EXTENSIONS)))
    return list(dict.fromkeys(os.path.abspath(m) for m in models))  # a model named twice runs once


def clean_name(text):
    """A folder name from `text`: letters, digits, '.', '_' and '-' kept, the rest '_'; no leading
    dot (never '.' or '..'), at most 100 characters."""
    return re.sub(r'[^A-Za-z0-9._-]', '_', text).lstrip('.')[:100] or 'model'


def unique_names(models):
    """Per model (absolute paths, no two alike), a folder name no other model of the batch shares,
    compared without case (a folder on a case-insensitive disk is one): the file name without its
    extension; where that repeats, the path relative to the models' common folder (a/sp.obj ->
    a_sp), then with its extension (sp.obj, sp.off -> sp.obj, sp.off); a name still taken gets -2,
    -3... in the order of the paths. The same models give the same names, in any order."""
    common = os.path.commonpath([os.path.dirname(m) for m in models])
    first = {m: clean_name(os.path.splitext(os.path.basename(m))[0]) for m in models}
    for longer in (lambda m: os.path.splitext(os.path.relpath(m, common))[0], lambda m: os.path.relpath(m, common)):
        counts = {}
        for n in first.values():
            counts[n.lower()] = counts.get(n.lower(), 0) + 1
        first = {m: clean_name(longer(m)) if counts[n.lower()] > 1 else n for m, n in first.items()}
    wanted = {n.lower() for n in first.values()}
    given, names = set(), {}
    for m in sorted(models):
        name, k = first[m], 1
        while name.lower() in given or (k > 1 and name.lower() in wanted):
            k += 1
            name = '%s-%d' % (first[m], k)
        given.add(name.lower())
        names[m] = name
    return [names[m] for m in models]


def command_for(step, arg, model, name, folder, max_memory):
    """The sdm command line of one step, and the files it writes."""
    out = lambda suffix: os.path.join(folder, name + suffix)
    memory = ['--max-memory', max_memory] if max_memory else []
    if step == 'skeleton':
        return ['skeleton', model, '-o', out('.skeleton.json'), '--json'], [out('.skeleton.json')]
    if step == 'stm':
        return ['stm', model, '-o', out('.layout.json'), '--json'], [out('.layout.json')]
    if step == 'encode':
        return ['encode', model, '-o', out('.exr'), '--json'] + memory, [out('.exr')]
    if step == 'roundtrip':
        return ['roundtrip', model, '--json'] + memory, []
    return ['transfer', '--source', arg, '--target', model, '-o', out('.transfer.obj'), '--json'] + memory, [out('.transfer.obj')]


FIGURES = {'stm': ('coverage',), 'encode': ('base_faces', 'carried'), 'roundtrip': ('rms', 'hausdorff'),
           'skeleton': ('nodes',), 'transfer': ('fit_rms',)}


def last_json(text):
    """The last JSON object a command printed on stdout, or {}."""
    at = text.rfind('{\n')
    while at >= 0:
        try:
            return json.loads(text[at:])
        except ValueError:
            at = text.rfind('{\n', 0, at)
    return {}


# ---- one model, on a worker --------------------------------------------------------------------

def resident_bytes(pid):
    try:
        with open('/proc/%d/status' % pid) as f:
            for line in f:
                if line.startswith('VmRSS:'):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def stop_child(p, grace=1.0):
    """Ends the command `p` (its process group): SIGTERM first, so that sdm removes its temporary
    files, SIGKILL after `grace` seconds; returns its (stdout, stderr)."""
    for sig, wait in ((signal.SIGTERM, grace), (signal.SIGKILL, None)):
        try:
            os.killpg(p.pid, sig)
        except OSError:
            pass
        try:
            return p.communicate(timeout=wait)
        except subprocess.TimeoutExpired:
            continue
    return '', ''


def run_watched(argv, deadline, memory_limit, running_file=''):
    """Runs argv; stops it past `deadline` (time.monotonic), above `memory_limit` bytes of resident
    memory or once `running_file` is gone (the batch was interrupted). Returns (exit code or None,
    stdout, stderr, 'timeout'/'memory'/'interrupted'/'')."""
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors='replace',
                         start_new_session=True)
    killed = ''
    out, err = '', ''
    try:
        while True:
            try:
                out, err = p.communicate(timeout=0.2)
                break
            except subprocess.TimeoutExpired:
                if time.monotonic() > deadline:
                    killed = 'timeout'
                elif memory_limit and resident_bytes(p.pid) > memory_limit:
                    killed = 'memory'
                elif running_file and not os.path.exists(running_file):
                    killed = 'interrupted'
                if killed:
                    out, err = stop_child(p)
                    break
    except BaseException:  # the task itself interrupted: the command does not outlive it
        stop_child(p)
        raise
    return (None if killed else p.returncode), out, err, killed


def error_line(stderr):
    """The line of a command's stderr that names its failure (the last 'failed'/'error' line)."""
    lines = [l.strip() for l in stderr.splitlines() if l.strip()]
    for l in reversed(lines):
        if 'failed' in l or 'error' in l.lower() or 'cannot' in l:
            return l[:500]
    return lines[-1][:500] if lines else ''


def file_key(path):
    """What a rerun compares to know a file unchanged: its size, modification time and SHA-256;
    None when it cannot be read (the command then says why)."""
    try:
        h = hashlib.sha256()
        with open(path, 'rb') as f:
            st = os.fstat(f.fileno())
            for block in iter(lambda: f.read(1 << 20), b''):
                h.update(block)
        return {'size': st.st_size, 'mtime_ns': st.st_mtime_ns, 'sha256': h.hexdigest()}
    except OSError:
        return None


def same_content(a, b):
    return bool(a) and bool(b) and a.get('size') == b.get('size') and a.get('sha256') == b.get('sha256')


RECORD = 'batch.json'
RECORD_ONLY = ('input', 'sources')  # in batch.json, not in the summary's rows


def finished_before(folder, steps, keys):
    """The row a previous run left in folder/batch.json when it finished these steps on the same
    content (`keys`: the model's and the transfer sources' file_key) and every output it names is
    there; else None."""
    try:
        with open(os.path.join(folder, RECORD), encoding='utf-8') as f:
            row = json.load(f)
    except (OSError, ValueError):
        return None
    if not isinstance(row, dict) or row.get('status') != STATUS_OK or row.get('steps') != step_words(steps):
        return None
    sources = row.get('sources') or {}
    if not same_content(row.get('input'), keys['input']) or set(sources) != set(keys['sources']):
        return None
    if not all(same_content(sources[a], k) for a, k in keys['sources'].items()):
        return None
    return row if all(os.path.exists(f) for f in row.get('outputs', [])) else None


def step_words(steps):
    return [s + (':' + a if a else '') for s, a in steps]


def write_record(folder, row, keys):
    """batch.json, last and atomically: its presence says the outputs are complete for this content.
    Returns '' or why it could not be written (the temporary removed)."""
    tmp = os.path.join(folder, '.batch.json.tmp')
    try:
        with open(tmp, 'w', encoding='utf-8') as f:
            json.dump(dict(row, **keys), f, indent=1)
        os.replace(tmp, os.path.join(folder, RECORD))
        return ''
    except OSError as e:
        try:
            os.remove(tmp)
        except OSError:
            pass
        return 'its outputs are complete, but its record %s could not be written (%s): it runs again next time' % (
            RECORD, e.strerror or e)


def run_steps(row, steps, model, name, folder, job):
    """The commands of `steps`, one after the other, until one fails; fills `row`."""
    start = time.monotonic()
    for step, arg in steps:
        args, outputs = command_for(step, arg, model, name, folder, job['max_memory'])
        code, out, err, killed = run_watched([job['sdm']] + args, start + job['timeout'], job['memory_limit'], job['running_file'])
        row['seconds_' + step] = round(time.monotonic() - start - sum(v for k, v in row.items() if k.startswith('seconds_')), 3)
        if killed or code != 0:
            row['status'] = {'timeout': 'timeout', 'memory': 'over memory', 'interrupted': 'interrupted'}.get(killed, 'failed')
            row['exit_code'] = -9 if killed else code
            row['failed_step'] = step
            row['error'] = {'timeout': 'killed after %.0f s (--timeout)' % job['timeout'],
                            'memory': 'killed above %s resident (--max-memory)' % job['memory_text'],
                            'interrupted': 'stopped: the batch was interrupted'}.get(killed) or error_line(err)
            break
        figures = last_json(out)
        for key in FIGURES.get(step, ()):
            if key in figures and not isinstance(figures[key], (dict, list)):
                row['%s_%s' % (step, key)] = figures[key]
        row['outputs'] += outputs
    row['seconds'] = round(time.monotonic() - start, 3)


def run_model(model, name, outdir, steps, job):
    """Every step for one model (a Dask task): its summary row. Never raises for the model's faults.
    `job`: sdm, timeout, memory_limit (bytes), max_memory (the text passed to the commands) and
    running_file (the batch's marker; the commands stop once it is gone)."""
    folder = os.path.join(outdir, name)
    keys = {'input': file_key(model), 'sources': {a: file_key(a) for _, a in steps if a}}
    row = {'model': shown(model), 'name': name, 'status': STATUS_OK, 'exit_code': 0, 'error': '', 'failed_step': '',
           'input_sha256': (keys['input'] or {}).get('sha256', ''), 'steps': step_words(steps), 'outputs': [], 'seconds': 0.0}
    before = finished_before(folder, steps, keys)
    if before:
        for k in RECORD_ONLY:
            before.pop(k, None)
        return dict(before, model=shown(model), name=name, status=STATUS_SKIPPED, seconds=0.0)
    try:
        os.makedirs(folder, exist_ok=True)
        if os.path.lexists(os.path.join(folder, RECORD)):
            os.remove(os.path.join(folder, RECORD))  # another content's record: never a skip for this one
    except OSError as e:
        return dict(row, status='failed', exit_code=-1, error='cannot write its folder %s: %s' % (shown(folder), e.strerror or e))
    run_steps(row, steps, model, name, folder, job)
    if row['status'] != STATUS_OK and not os.listdir(folder):
        os.rmdir(folder)  # nothing left behind for a model that wrote nothing
    if row['status'] == STATUS_OK:
        row['error'] = write_record(folder, row, keys)
    return row


# ---- the batch ---------------------------------------------------------------------------------

def parse_memory(text):
    """'8G', '512M', '1.5G' or bytes -> bytes (0 for none); raises BatchError."""
    if not text:
        return 0
    m = re.fullmatch(r'\s*([0-9]+(?:\.[0-9]*)?|\.[0-9]+)\s*([KMGT]?)B?\s*', text.upper())
    if not m:
        raise BatchError("--max-memory '%s' is not a size (write e.g. 8G, 512M or a number of bytes)" % text)
    size = int(float(m.group(1)) * 1024 ** ' KMGT'.index(m.group(2) or ' '))
    if size < 1:
        raise BatchError("--max-memory '%s' is no memory at all (leave the option out for no limit)" % text)
    return size


def check_limits(workers, timeout):
    """Raises BatchError naming --workers or --timeout when it is out of range."""
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= 256:
        raise BatchError('--workers %s is out of range: the local cluster takes 1 to 256 worker processes' % workers)
    if not isinstance(timeout, (int, float)) or isinstance(timeout, bool) or not (0 < timeout < math.inf):
        raise BatchError("--timeout %s is out of range: a model's time limit must be a positive, finite number of seconds" % timeout)


def replace_all(files):
    """Writes each (path, write) in `files`: every one to a temporary name first (write(f) fills
    it), then all renamed; on any error, every temporary is removed and the error propagates, the
    files as they were."""
    temporaries = []
    try:
        for path, write in files:
            tmp = os.path.join(os.path.dirname(path), '.%s.tmp' % os.path.basename(path))
            temporaries.append(tmp)
            with open(tmp, 'w', encoding='utf-8', newline='') as f:
                write(f)
        for (path, _), tmp in zip(files, temporaries):
            os.replace(tmp, path)
    except BaseException:
        for tmp in temporaries:
            try:
                os.remove(tmp)
            except OSError:
                pass
        raise


def write_summary(rows, outdir):
    """summary.json and summary.csv in outdir (both written to temporary names, then moved);
    raises BatchFailure, both left as they were, when they cannot be written (a full disk)."""
    keys = ['name', 'status', 'exit_code', 'seconds', 'failed_step', 'error', 'model']
    keys += sorted({k for r in rows for k in r if k not in keys and k not in ('steps', 'outputs')})
    summary = {'models': len(rows), 'ok': sum(r['status'] in (STATUS_OK, STATUS_SKIPPED) for r in rows), 'rows': rows}

    def write_csv(f):
        w = csv.DictWriter(f, fieldnames=keys, extrasaction='ignore')
        w.writeheader()
        for r in rows:
            w.writerow(r)
    try:
        replace_all([(os.path.join(outdir, 'summary.json'), lambda f: json.dump(summary, f, indent=1)),
                     (os.path.join(outdir, 'summary.csv'), write_csv)])
    except OSError as e:
        raise BatchFailure('cannot write the summary (summary.json, summary.csv) in %s: %s. The models\' outputs are kept: '
                           'free space or fix the folder and run the same command again (finished models are skipped)'
                           % (shown(outdir), e.strerror or e))
    return summary


def progress_line(done, total, row, width=30):
    filled = int(width * done / total)
    return '[%s%s] %d/%d %s: %s (%.1f s)%s' % ('#' * filled, '-' * (width - filled), done, total, row['name'], row['status'],
                                             row['seconds'], ', ' + row['error'] if row['error'] else '')


class quiet_signals:
    """While stopping or closing: SIGINT and SIGTERM are noted, not raised (in the main thread;
    elsewhere nothing changes). `signum` says the first one noted."""

    def __enter__(self):
        self.signum, self.previous = 0, {}
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self.previous[sig] = signal.signal(sig, self.note)
        return self

    def note(self, signum, frame):
        self.signum = self.signum or signum

    def __exit__(self, *exc):
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        return False


def local_cluster(workers):
    """A local cluster of `workers` processes, one thread each (the sdm commands use the cores). Its
    workers start with SIGINT ignored (a disposition they inherit), so that Ctrl-C reaches the
    batch, which stops the commands, instead of raising KeyboardInterrupt in every worker (a page of
    tracebacks each); for the second or two the cluster takes to start, Ctrl-C is ignored and
    SIGTERM waits until it is up."""
    import logging
    from distributed import LocalCluster
    with quiet_signals() as quiet:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               memory_limit=0, silence_logs=logging.ERROR)
    if quiet.signum:
        with quiet_signals():
            cluster.close()
        raise Interrupted(quiet.signum)
    return cluster


def client_for(scheduler, workers):
    """A Dask client: of the scheduler at `scheduler`, else of a local cluster of `workers`
    processes (one thread each: the sdm commands use the cores)."""
    try:
        from distributed import Client
    except ImportError:
        raise BatchError('sdm batch needs Dask: apt install python3-distributed (scripts/install-deps.sh installs it)')
    if scheduler:
        try:
            return Client(scheduler, timeout=30), None
        except (OSError, ValueError, TypeError) as e:
            raise BatchError('cannot reach the Dask scheduler at %s (%s); check --scheduler tcp://HOST:PORT' % (scheduler, e))
    cluster = local_cluster(workers)
    return Client(cluster), cluster


def prepare_outdir(outdir):
    """The output folder, made, as an absolute path, and the batch's marker in it (a hidden file the
    tasks watch: once it is gone, they stop their commands); raises BatchError when the folder is a
    file or cannot be written."""
    if os.path.lexists(outdir) and not os.path.isdir(outdir):
        raise BatchError('-o %s: it is a file, not a folder; name a folder for the outputs' % shown(outdir))
    try:
        os.makedirs(outdir, exist_ok=True)
        outdir = os.path.abspath(outdir)
        running = os.path.join(outdir, '.batch-running-%d' % os.getpid())
        open(running, 'w').close()
    except OSError as e:
        raise BatchError('-o %s: cannot write there (%s); name a folder you can write' % (shown(outdir), e.strerror or e))
    return outdir, running


def collect(client, futures, models, names, progress):
    """The tasks' rows as they finish, in the models' order."""
    from distributed import as_completed
    rows = [None] * len(models)
    for done, future in enumerate(as_completed(futures), 1):
        i = futures[future]
        try:
            rows[i] = future.result()
        except Exception as e:  # the task itself failed (a worker lost): recorded, the batch goes on
            rows[i] = {'model': shown(models[i]), 'name': names[i], 'status': 'failed', 'exit_code': -1,
                       'error': 'task failed: %s' % e, 'failed_step': '', 'seconds': 0.0}
        if progress:
            print(progress_line(done, len(models), rows[i]), file=sys.stderr, flush=True)
    return rows


def close(client, cluster, running, futures=()):
    """Stops what runs and closes the cluster: `running` removed first (the tasks stop their
    commands, which remove their temporary files), up to 15 s for the tasks to return."""
    try:
        os.remove(running)
    except OSError:
        pass
    if futures:
        from distributed import wait
        try:
            wait(list(futures), timeout=15)
        except Exception:
            pass
    client.close()
    if cluster:
        cluster.close()


def run_batch(inputs, outdir, steps, sdm='sdm', scheduler=None, workers=2, timeout=3600.0, max_memory='', progress=True):
    """Runs `steps` (parse_steps's pairs, or the --do text) on every model of `inputs` (see
    find_models) into `outdir`; returns the summary rows, in the models' order, and writes
    summary.csv and summary.json there. Raises BatchError for bad arguments, BatchFailure when the
    summary cannot be written, KeyboardInterrupt (Interrupted under main) once the running commands
    are stopped."""
    if isinstance(steps, str):
        steps = parse_steps(steps)
    check_limits(workers, timeout)
    memory_limit = parse_memory(max_memory)
    models = find_models(inputs)
    names = unique_names(models)
    outdir, running = prepare_outdir(outdir)
    job = {'sdm': sdm, 'timeout': timeout, 'memory_limit': memory_limit, 'max_memory': str(memory_limit) if memory_limit else '',
           'memory_text': max_memory, 'running_file': running}
    try:
        client, cluster = client_for(scheduler, workers)
    except BaseException:
        os.remove(running)
        raise
    try:
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers elsewhere need not import this file
    except (ImportError, ValueError):
        pass
    futures = {}
    try:
        for i, (m, n) in enumerate(zip(models, names)):
            futures[client.submit(run_model, m, n, outdir, steps, job, key='sdm-%s-%d' % (n, i), pure=False)] = i
        rows = collect(client, futures, models, names, progress)
    except BaseException:
        with quiet_signals():
            close(client, cluster, running, futures)
        raise
    with quiet_signals() as quiet:
        close(client, cluster, running)
    if quiet.signum:
        raise Interrupted(quiet.signum)
    try:
        write_summary(rows, outdir)
    except BatchFailure as e:
        e.rows = rows  # the table can still be printed
        raise
    return rows


def print_table(rows, out=sys.stdout):
    out.write('| model | status | exit | seconds | error |\n|---|---|---|---|---|\n')
    for r in rows:
        out.write('| %s | %s | %s | %.1f | %s |\n' % (r['name'], r['status'], r['exit_code'], r['seconds'], r['error']))


def arguments():
    ap = argparse.ArgumentParser(prog='sdm batch', description=__doc__.split('\n\n')[1], formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='\n\n'.join(__doc__.split('\n\n')[2:]))
    ap.add_argument('inputs', nargs='+', help='mesh files, folders of them, or manifests (.txt, one path a line)')
    ap.add_argument('-o', '--output', required=True, help='folder for the outputs and the summary')
    ap.add_argument('--do', default='stm,encode', help='steps for each model, comma-separated (default: stm,encode)')
    ap.add_argument('--scheduler', help='address of a Dask scheduler (tcp://HOST:8786); default: a local cluster')
    ap.add_argument('--workers', type=int, default=2, help='processes of the local cluster, 1 to 256 (default 2)')
    ap.add_argument('--timeout', type=float, default=3600, help="seconds a model's steps may take in all (default 3600)")
    ap.add_argument('--max-memory', default='', help="resident memory a model's command may use (e.g. 8G); above it the model is killed")
    ap.add_argument('--sdm', default=os.environ.get('SDM_BINARY', 'sdm'), help='the sdm program to run (default: sdm on PATH)')
    ap.add_argument('--json', action='store_true', help='print the summary as JSON instead of a table')
    ap.add_argument('--report', action='store_true',
                    help='also write OUTDIR/report.html: a self-contained page with a row per model (status, reason, '
                         'figures, pictures of the model, its skeleton and its STM checker), sortable by any column')
    ap.add_argument('--up', default='', help="the models' up axis for the report's pictures (x, y, z, -x, -y, -z; default: "
                                              "as sdm render decides)")
    return ap


def write_report(a, rows):
    """OUTDIR/report.html for `rows` (--report); its path, or raises BatchFailure."""
    import sdm_batch_report  # beside this file
    try:
        return sdm_batch_report.write_report(rows, find_models(a.inputs), a.output, a.sdm, (STATUS_OK, STATUS_SKIPPED),
                                             up=a.up, workers=a.workers)
    except OSError as e:
        raise BatchFailure('cannot write the report %s: %s' % (shown(os.path.join(a.output, 'report.html')), e.strerror or e))


def raise_interrupted(signum, frame):
    raise Interrupted(signum)


def main(argv=None):
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.reconfigure(errors='backslashreplace')  # a model's name never stops the report
        except (AttributeError, ValueError):
            pass
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, raise_interrupted)
    try:
        a = arguments().parse_args(argv)
        if a.up and a.up.lstrip('+-') not in ('x', 'y', 'z'):
            raise BatchError("--up '%s' is not an axis: give x, y, z, -x, -y or -z" % a.up)
        rows = run_batch(a.inputs, a.output, a.do, sdm=a.sdm, scheduler=a.scheduler, workers=a.workers, timeout=a.timeout,
                         max_memory=a.max_memory, progress=True)
        report = write_report(a, rows) if a.report else None
        if a.json:
            json.dump(json.load(open(os.path.join(a.output, 'summary.json'), encoding='utf-8')), sys.stdout, indent=1)
            print()
        else:
            print_table(rows)
            print('summary: %s, %s' % (shown(os.path.join(a.output, 'summary.csv')), shown(os.path.join(a.output, 'summary.json'))))
            if report:
                print('report: %s' % shown(report))
        return 0 if all(r['status'] in (STATUS_OK, STATUS_SKIPPED) for r in rows) else 1
    except BatchError as e:
        print('sdm batch: %s' % e, file=sys.stderr)
        return 2
    except BatchFailure as e:
        if getattr(e, 'rows', None):
            print_table(e.rows)
        print('sdm batch: failed: %s' % e, file=sys.stderr)
        return 1
    except KeyboardInterrupt as e:
        signum = getattr(e, 'signum', signal.SIGINT)
        print('sdm batch: interrupted (%s): the running commands were stopped and removed their temporary files; finished '
              'models keep their outputs, and the same command goes on from there' % signal.Signals(signum).name, file=sys.stderr)
        return 128 + signum
    except OSError as e:  # the folders or the terminal failing under the batch
        print('sdm batch: failed: %s' % e, file=sys.stderr)
        return 1


if __name__ == '__main__':
    sys.exit(main())

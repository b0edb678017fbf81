#!/usr/bin/python3
"""sdm batch: the sdm commands over a folder or a manifest of models, each model a task on Dask.

Every model runs as its own task on a Dask cluster (Debian's python3-distributed): a local one of
--workers processes by default, or the scheduler at --scheduler ADDRESS. A task runs the `sdm`
commands of --do for its model, one after the other, as child processes, under a time limit
(--timeout, the task's wall time) and a memory limit (--max-memory, the resident memory of the
command running; also passed to each command's own --max-memory check), so that a model that
hangs, crashes or swells is recorded and the batch goes on. Outputs go to OUTDIR/NAME/ (NAME: the
model's file name without its extension, made unique); a task that finishes writes
OUTDIR/NAME/batch.json last, and a later run skips every model whose batch.json says it finished
with the same steps and whose outputs are all there. At the end: OUTDIR/summary.csv and
OUTDIR/summary.json, one row per model (status, exit code, error, seconds, the commands' figures).

Steps (--do, comma-separated, in this order for each model):
  skeleton            sdm skeleton MODEL -o NAME.skeleton.json
  stm                 sdm stm MODEL -o NAME.layout.json          (figure: coverage)
  encode              sdm encode MODEL -o NAME.exr               (figures: base faces, carried)
  roundtrip           sdm roundtrip MODEL                        (figures: rms, hausdorff)
  transfer:SOURCE     sdm transfer --source SOURCE --target MODEL -o NAME.transfer.obj

From Python: `import sdm_batch; rows = sdm_batch.run_batch(["a.obj", "b.off"], "out", "stm")`, in a
script under `if __name__ == "__main__":` (the local cluster's workers start by importing it).
Exit codes: 0 when every model finished, 1 when some failed (the table says which), 2 for bad
arguments (a missing input, an unknown step, no Dask).
"""
import argparse
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

MESH_EXTENSIONS = ('.obj', '.off', '.ply', '.stl', '.glb', '.gltf')
STATUS_OK, STATUS_SKIPPED = 'ok', 'skipped (done before)'


class BatchError(Exception):
    """Bad arguments: the message names the problem; exit code 2."""


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
        if os.path.isdir(item):
            models += sorted(os.path.join(item, f) for f in os.listdir(item) if f.lower().endswith(MESH_EXTENSIONS))
        elif item.lower().endswith('.txt') and os.path.isfile(item):
            base = os.path.dirname(os.path.abspath(item))
            for line in open(item, encoding='utf-8'):
                line = line.split('#', 1)[0].strip()
                if line:
                    models.append(line if os.path.isabs(line) else os.path.join(base, line))
        elif os.path.exists(item):
            models.append(item)
        else:
            raise BatchError('%s: no such file or folder' % item)
    if not models:
        raise BatchError('no models found in %s (mesh files: %s)' % (' '.join(inputs), ' '.join(MESH_EXTENSIONS)))
    return [os.path.abspath(m) for m in models]


def unique_names(models):
    """Per model, a folder name: the file name without extension, numbered where names repeat."""
    names, seen = [], {}
    for m in models:
        stem = re.sub(r'[^A-Za-z0-9._-]', '_', os.path.splitext(os.path.basename(m))[0]) or 'model'
        seen[stem] = seen.get(stem, 0) + 1
        names.append(stem if seen[stem] == 1 else '%s-%d' % (stem, seen[stem]))
    return names


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


def run_watched(argv, deadline, memory_limit):
    """Runs argv; kills it past `deadline` (time.monotonic) or above `memory_limit` bytes of
    resident memory. Returns (exit code or None, stdout, stderr, 'timeout'/'memory'/'')."""
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    killed = ''
    out, err = '', ''
    while True:
        try:
            out, err = p.communicate(timeout=0.2)
            break
        except subprocess.TimeoutExpired:
            if time.monotonic() > deadline:
                killed = 'timeout'
            elif memory_limit and resident_bytes(p.pid) > memory_limit:
                killed = 'memory'
            if killed:
                os.killpg(p.pid, signal.SIGKILL)
                out, err = p.communicate()
                break
    return (None if killed else p.returncode), out, err, killed


def error_line(stderr):
    """The line of a command's stderr that names its failure (the last 'failed'/'error' line)."""
    lines = [l.strip() for l in stderr.splitlines() if l.strip()]
    for l in reversed(lines):
        if 'failed' in l or 'error' in l.lower() or 'cannot' in l:
            return l[:500]
    return lines[-1][:500] if lines else ''


def finished_before(folder, steps):
    """The row a previous run left in folder/batch.json when it finished these steps and every
    output it names is there; else None."""
    try:
        row = json.load(open(os.path.join(folder, 'batch.json')))
    except (OSError, ValueError):
        return None
    if row.get('status') != STATUS_OK or row.get('steps') != [s + (':' + a if a else '') for s, a in steps]:
        return None
    return row if all(os.path.exists(f) for f in row.get('outputs', [])) else None


def run_model(model, name, outdir, steps, sdm, timeout, memory_limit, max_memory):
    """Every step for one model (a Dask task): its summary row. Never raises for the model's faults."""
    folder = os.path.join(outdir, name)
    os.makedirs(folder, exist_ok=True)
    before = finished_before(folder, steps)
    if before:
        before['status'] = STATUS_SKIPPED
        before['seconds'] = 0.0
        return before
    start = time.monotonic()
    row = {'model': model, 'name': name, 'status': STATUS_OK, 'exit_code': 0, 'error': '', 'failed_step': '',
           'steps': [s + (':' + a if a else '') for s, a in steps], 'outputs': [], 'seconds': 0.0}
    for step, arg in steps:
        args, outputs = command_for(step, arg, model, name, folder, max_memory)
        code, out, err, killed = run_watched([sdm] + args, start + timeout, memory_limit)
        row['seconds_' + step] = round(time.monotonic() - start - sum(v for k, v in row.items() if k.startswith('seconds_')), 3)
        if killed or code != 0:
            row['status'] = {'timeout': 'timeout', 'memory': 'over memory'}.get(killed, 'failed')
            row['exit_code'] = -9 if killed else code
            row['failed_step'] = step
            row['error'] = ('killed after %.0f s (--timeout)' % timeout if killed == 'timeout' else
                            'killed above %s resident (--max-memory)' % max_memory if killed else error_line(err))
            break
        figures = last_json(out)
        for key in FIGURES.get(step, ()):
            if key in figures and not isinstance(figures[key], (dict, list)):
                row['%s_%s' % (step, key)] = figures[key]
        row['outputs'] += outputs
    row['seconds'] = round(time.monotonic() - start, 3)
    if row['status'] != STATUS_OK and not os.listdir(folder):
        os.rmdir(folder)  # nothing left behind for a model that wrote nothing
    if row['status'] == STATUS_OK:  # last, and atomically: its presence says the outputs are complete
        tmp = os.path.join(folder, '.batch.json.tmp')
        with open(tmp, 'w') as f:
            json.dump(row, f, indent=1)
        os.replace(tmp, os.path.join(folder, 'batch.json'))
    return row


# ---- the batch ---------------------------------------------------------------------------------

def parse_memory(text):
    """'8G', '512M', '1.5G' or bytes -> bytes (0 for none); raises BatchError."""
    if not text:
        return 0
    m = re.fullmatch(r'\s*([0-9.]+)\s*([KMGT]?)B?\s*', text.upper())
    if not m:
        raise BatchError("--max-memory '%s' is not a size (e.g. 8G, 512M)" % text)
    return int(float(m.group(1)) * 1024 ** ' KMGT'.index(m.group(2) or ' '))


def write_summary(rows, outdir):
    """summary.json and summary.csv in outdir (written to temporary names, then moved)."""
    keys = ['name', 'status', 'exit_code', 'seconds', 'failed_step', 'error', 'model']
    keys += sorted({k for r in rows for k in r if k not in keys and k not in ('steps', 'outputs')})
    tmp = os.path.join(outdir, '.summary.json.tmp')
    with open(tmp, 'w') as f:
        json.dump({'models': len(rows), 'ok': sum(r['status'] in (STATUS_OK, STATUS_SKIPPED) for r in rows), 'rows': rows}, f, indent=1)
    os.replace(tmp, os.path.join(outdir, 'summary.json'))
    tmp = os.path.join(outdir, '.summary.csv.tmp')
    with open(tmp, 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction='ignore')
        w.writeheader()
        for r in rows:
            w.writerow(r)
    os.replace(tmp, os.path.join(outdir, 'summary.csv'))


def progress_line(done, total, row, width=30):
    filled = int(width * done / total)
    return '[%s%s] %d/%d %s: %s (%.1f s)%s' % ('#' * filled, '-' * (width - filled), done, total, row['name'], row['status'],
                                             row['seconds'], ', ' + row['error'] if row['error'] else '')


def client_for(scheduler, workers):
    """A Dask client: of the scheduler at `scheduler`, else of a local cluster of `workers`
    processes (one thread each: the sdm commands use the cores)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise BatchError('sdm batch needs Dask: apt install python3-distributed (scripts/install-deps.sh installs it)')
    import logging
    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           memory_limit=0, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def run_batch(inputs, outdir, steps, sdm='sdm', scheduler=None, workers=2, timeout=3600.0, max_memory='', progress=True):
    """Runs `steps` (parse_steps's pairs, or the --do text) on every model of `inputs` (see
    find_models) into `outdir`; returns the summary rows, in the models' order, and writes
    summary.csv and summary.json there."""
    if isinstance(steps, str):
        steps = parse_steps(steps)
    models = find_models(inputs)
    names = unique_names(models)
    memory_limit = parse_memory(max_memory)
    os.makedirs(outdir, exist_ok=True)
    outdir = os.path.abspath(outdir)
    client, cluster = client_for(scheduler, workers)
    try:
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers elsewhere need not import this file
    except (ImportError, ValueError):
        pass
    from distributed import as_completed
    try:
        futures = {client.submit(run_model, m, n, outdir, steps, sdm, timeout, memory_limit, max_memory, key='sdm-' + n + '-' + str(i),
                                 pure=False): i for i, (m, n) in enumerate(zip(models, names))}
        rows = [None] * len(models)
        for done, future in enumerate(as_completed(futures), 1):
            i = futures[future]
            try:
                rows[i] = future.result()
            except Exception as e:  # the task itself failed (a worker lost): recorded, the batch goes on
                rows[i] = {'model': models[i], 'name': names[i], 'status': 'failed', 'exit_code': -1, 'error': 'task failed: %s' % e,
                           'failed_step': '', 'seconds': 0.0}
            if progress:
                print(progress_line(done, len(models), rows[i]), file=sys.stderr, flush=True)
    finally:
        client.close()
        if cluster:
            cluster.close()
    write_summary(rows, outdir)
    return rows


def print_table(rows, out=sys.stdout):
    out.write('| model | status | exit | seconds | error |\n|---|---|---|---|---|\n')
    for r in rows:
        out.write('| %s | %s | %s | %.1f | %s |\n' % (r['name'], r['status'], r['exit_code'], r['seconds'], r['error']))


def number_in(lo, hi, kind=float, above=False):
    """An argparse type: a finite number from lo (excluded with above) to hi; nan, inf and values
    outside are refused (exit 2) with the value and the range, as the sdm commands refuse them."""
    span = '%s%g, %g]' % ('(' if above else '[', lo, hi)

    def parse(text):
        try:
            x = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError("'%s' is not a number; give one in %s" % (text, span))
        if not (math.isfinite(x) and (x > lo if above else x >= lo) and x <= hi):
            raise argparse.ArgumentTypeError('%s is out of range; give a finite number in %s' % (text, span))
        return x
    return parse


def main(argv=None):
    ap = argparse.ArgumentParser(prog='sdm batch', description=__doc__.split('\n\n')[1], formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='\n\n'.join(__doc__.split('\n\n')[2:]))
    ap.add_argument('inputs', nargs='+', help='mesh files, folders of them, or manifests (.txt, one path a line)')
    ap.add_argument('-o', '--output', required=True, help='folder for the outputs and the summary')
    ap.add_argument('--do', default='stm,encode', help='steps for each model, comma-separated (default: stm,encode)')
    ap.add_argument('--scheduler', help='address of a Dask scheduler (tcp://HOST:8786); default: a local cluster')
    ap.add_argument('--workers', type=number_in(1, 1024, int), default=2, help='processes of the local cluster (default 2)')
    ap.add_argument('--timeout', type=number_in(0, 1e7, above=True), default=3600, help="seconds a model's steps may take in all (default 3600)")
    ap.add_argument('--max-memory', default='', help="resident memory a model's command may use (e.g. 8G); above it the model is killed")
    ap.add_argument('--sdm', default=os.environ.get('SDM_BINARY', 'sdm'), help='the sdm program to run (default: sdm on PATH)')
    ap.add_argument('--json', action='store_true', help='print the summary as JSON instead of a table')
    a = ap.parse_args(argv)
    try:
        if a.workers < 1 or a.timeout <= 0:
            raise BatchError('--workers must be at least 1 and --timeout positive')
        rows = run_batch(a.inputs, a.output, a.do, sdm=a.sdm, scheduler=a.scheduler, workers=a.workers, timeout=a.timeout,
                         max_memory=a.max_memory)
    except BatchError as e:
        print('sdm batch: %s' % e, file=sys.stderr)
        return 2
    if a.json:
        json.dump(json.load(open(os.path.join(a.output, 'summary.json'))), sys.stdout, indent=1)
        print()
    else:
        print_table(rows)
        print('summary: %s, %s' % (os.path.join(a.output, 'summary.csv'), os.path.join(a.output, 'summary.json')))
    return 0 if all(r['status'] in (STATUS_OK, STATUS_SKIPPED) for r in rows) else 1


if __name__ == '__main__':
    sys.exit(main())

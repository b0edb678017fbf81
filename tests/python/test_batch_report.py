"""Tests of `sdm batch --report` (python/sdm_batch_report.py; run by CTest as python.batch_report):
the five wild models of ../shared/models and a broken file, their report opened in headless
Chromium: every thumbnail loads, the broken file's row is marked failed with its reason, and a sort
named in the page's address orders the rows by that column's values.

Usage: test_batch_report.py SDM_BINARY SHARED_MODELS
Exits 77 (skipped, with a message) when Chromium or the shared models are missing.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

SDM = sys.argv[1] if len(sys.argv) > 1 else 'sdm'
SHARED = sys.argv[2] if len(sys.argv) > 2 else ''
WILD = ('beetle.obj', 'cow.obj', 'stanford-bunny.obj', 'suzanne.obj', 'teapot.obj')
failures = []


def check(ok, what):
    print(('ok   ' if ok else 'FAIL ') + what)
    if not ok:
        failures.append(what)


def chromium():
    for name in ('chromium', 'chromium-browser', 'google-chrome'):
        path = shutil.which(name)
        if path:
            return path
    return None


def dom(browser, page, fragment, profile):
    """The page's DOM after its scripts ran, as headless Chromium dumps it."""
    p = subprocess.run([browser, '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                        '--disable-background-networking', '--disable-component-update', '--disable-sync',
                        '--user-data-dir=' + profile, '--virtual-time-budget=5000', '--dump-dom',
                        'file://' + page + fragment], capture_output=True, text=True, timeout=180)
    return p.stdout


def attribute(text, name):
    m = re.search(r'<body[^>]*\s%s="([^"]*)"' % name, text)
    return m.group(1) if m else None


def main():
    browser = chromium()
    wild = os.path.join(SHARED, 'wild')
    if browser is None:
        print('skipped: Chromium is not installed (bash scripts/install-deps.sh --tests installs it)')
        return 77
    if not all(os.path.isfile(os.path.join(wild, m)) for m in WILD):
        print('skipped: the wild models are not in %s' % wild)
        return 77
    with tempfile.TemporaryDirectory() as tmp:
        models = os.path.join(tmp, 'models')
        os.makedirs(models)
        for m in WILD:
            os.symlink(os.path.join(wild, m), os.path.join(models, m))
        with open(os.path.join(models, 'broken.off'), 'w') as f:
            f.write('OFF\n400 2 0\n0 0 0\n1 0 0\n')
        out = os.path.join(tmp, 'out')
        p = subprocess.run([SDM, 'batch', models, '-o', out, '--do', 'skeleton,stm', '--workers', '2', '--report'],
                           capture_output=True, text=True, timeout=900)
        print(p.stdout[-2000:] + p.stderr[-2000:])
        page = os.path.join(out, 'report.html')
        check(p.returncode == 1 and os.path.isfile(page), 'the batch with a broken file exits 1 and writes report.html')
        if not os.path.isfile(page):
            return 1
        text = open(page, encoding='utf-8').read()
        check(not re.search(r'(src|href)="(https?:)?//', text), 'the page names nothing to fetch (self-contained)')
        profile = os.path.join(tmp, 'profile')
        shown = dom(browser, page, '', profile)
        images, loaded = attribute(shown, 'data-images'), attribute(shown, 'data-images-shown')
        # Each good model: the model, its skeleton and its STM checker.
        check(images == str(3 * len(WILD)) and loaded == images,
              'Chromium shows every thumbnail: %s of %s images loaded (want %d)' % (loaded, images, 3 * len(WILD)))
        failed = re.findall(r'<tr class="failed" data-name="([^"]*)">(.*?)</tr>', shown, re.S)
        check([n for n, _ in failed] == ['broken'] and 'no model picture' in failed[0][1] if failed else False,
              'the broken file\'s row is marked failed, its picture replaced by the reason')
        # Sorted by the skeleton's node count, largest first, from the page's address.
        ordered = dom(browser, page, '#sort=-skeleton_nodes', profile)
        check(attribute(ordered, 'data-sorted') == 'skeleton_nodes:down', 'the address sorts the table (data-sorted)')
        names = re.findall(r'<tr class="(?:ok|failed)" data-name="([^"]*)"', ordered)
        with open(os.path.join(out, 'summary.json'), encoding='utf-8') as f:
            nodes = {r['name']: r.get('skeleton_nodes', -1) for r in json.load(f)['rows']}
        want = sorted([n for n in nodes if nodes[n] != -1], key=lambda n: -nodes[n])
        got = [n for n in names if nodes.get(n, -1) != -1]
        check(got == want and len(got) == len(WILD),
              'rows by skeleton nodes, largest first: %s (%s)' % (got, [nodes[n] for n in got]))
    if failures:
        print('%d check(s) failed' % len(failures))
        return 1
    print('batch report: all checks passed')
    return 0


if __name__ == '__main__':
    sys.exit(main())

"""The report of an `sdm batch` run (`--report`): one self-contained HTML page, OUTDIR/report.html.

A row per model: its status and reason, the figures of summary.csv, and thumbnails drawn with
`sdm render` (the model; its skeleton over it when the batch made one; its STM checker when the
batch made a layout). Images are embedded as data: URIs and the page's script is inline, so the
page opens anywhere with nothing fetched at view time. Clicking a column's header sorts by it (again:
the other way); the page's address may name a sort, report.html#sort=COLUMN or #sort=-COLUMN.
A model whose pictures cannot be drawn (a broken file) gets its reason in their place.
"""
import base64
import html
import os
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

THUMB = 192  # pixels a side

PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>sdm batch: %(title)s</title>
<style>
body { font: 14px sans-serif; margin: 1em; }
table { border-collapse: collapse; }
th, td { border: 1px solid #ccc; padding: 4px 6px; vertical-align: middle; }
th { background: #eee; cursor: pointer; user-select: none; white-space: nowrap; }
th.sorted-up::after { content: " \\25B2"; } th.sorted-down::after { content: " \\25BC"; }
tr.failed td { background: #fde8e8; } tr.failed td.status { color: #a00; font-weight: bold; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.pics img { width: %(thumb)dpx; height: %(thumb)dpx; margin-right: 2px; border: 1px solid #ddd; }
td.error { max-width: 28em; font-size: 12px; }
</style></head>
<body data-rows="%(rows)d" data-failed="%(failed)d">
<h1>sdm batch: %(title)s</h1>
<p>%(summary)s</p>
<table id="models"><thead><tr>%(head)s</tr></thead><tbody>
%(body)s
</tbody></table>
<script>
(function () {
  var table = document.getElementById("models");
  var heads = table.tHead.rows[0].cells;
  function key(td) {
    var v = td.getAttribute("data-value");
    return v === null ? td.textContent : v;
  }
  function sortBy(column, down) {
    var body = table.tBodies[0], rows = Array.prototype.slice.call(body.rows);
    var numeric = heads[column].getAttribute("data-numeric") === "1";
    rows.sort(function (a, b) {
      var x = key(a.cells[column]), y = key(b.cells[column]);
      if (numeric) {
        x = x === "" ? Infinity : parseFloat(x);
        y = y === "" ? Infinity : parseFloat(y);
        return down ? (y === x ? 0 : (y > x ? 1 : -1)) : (x === y ? 0 : (x > y ? 1 : -1));
      }
      return down ? y.localeCompare(x) : x.localeCompare(y);
    });
    rows.forEach(function (r) { body.appendChild(r); });
    for (var i = 0; i < heads.length; ++i) heads[i].className = "";
    heads[column].className = down ? "sorted-down" : "sorted-up";
    document.body.setAttribute("data-sorted", heads[column].getAttribute("data-key") + (down ? ":down" : ":up"));
  }
  Array.prototype.forEach.call(heads, function (th, i) {
    th.addEventListener("click", function () { sortBy(i, th.className === "sorted-up"); });
  });
  function fromAddress() {
    var m = /sort=(-?)([A-Za-z0-9_]+)/.exec(location.hash);
    if (!m) return;
    for (var i = 0; i < heads.length; ++i)
      if (heads[i].getAttribute("data-key") === m[2]) sortBy(i, m[1] === "-");
  }
  window.addEventListener("hashchange", fromAddress);
  fromAddress();
  function countImages() {
    var imgs = document.images, shown = 0;
    for (var i = 0; i < imgs.length; ++i) if (imgs[i].complete && imgs[i].naturalWidth > 0) ++shown;
    document.body.setAttribute("data-images", imgs.length);
    document.body.setAttribute("data-images-shown", shown);
  }
  window.addEventListener("load", countImages);
})();
</script>
</body></html>
"""


def render(sdm, argv, timeout=120):
    """The PNG bytes `sdm render ARGV` draws, or (None, reason)."""
    with tempfile.TemporaryDirectory(prefix='sdm-report-') as folder:
        out = os.path.join(folder, 'thumb.png')
        try:
            p = subprocess.run([sdm, 'render'] + argv + ['-o', out, '--width', str(THUMB), '--height', str(THUMB)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout)
        except (OSError, subprocess.TimeoutExpired) as e:
            return None, 'render failed: %s' % e
        if p.returncode != 0 or not os.path.isfile(out):
            lines = [l for l in p.stderr.decode('utf-8', 'replace').splitlines() if l.strip()]
            return None, lines[-1] if lines else 'render failed (exit %d)' % p.returncode
        with open(out, 'rb') as f:
            return f.read(), ''


def thumbnails(sdm, row, model, outdir, up):
    """[(title, png bytes or None, reason)] for one summary row, its model's file `model`."""
    folder = os.path.join(outdir, row['name'])
    extra = ['--up', up] if up else []
    views = [('model', [model] + extra)]
    skeleton = os.path.join(folder, row['name'] + '.skeleton.json')
    layout = os.path.join(folder, row['name'] + '.layout.json')
    if os.path.isfile(skeleton):
        views.append(('skeleton', [model, '--skeleton', skeleton, '--no-texture'] + extra))
    if os.path.isfile(layout):
        views.append(('STM checker', [model, '--layout', layout, '--checker'] + extra))
    out = []
    for title, argv in views:
        png, reason = render(sdm, argv)
        out.append((title, png, reason))
    return out


def cell(value):
    """A table cell: numbers right-aligned with their value for sorting."""
    if isinstance(value, bool) or value is None:
        return '<td>%s</td>' % html.escape('' if value is None else str(value))
    if isinstance(value, (int, float)):
        text = ('%.4g' % value) if isinstance(value, float) else str(value)
        return '<td class="num" data-value="%r">%s</td>' % (value, text)
    return '<td>%s</td>' % html.escape(str(value))


def pictures(thumbs):
    parts = []
    for title, png, reason in thumbs:
        if png is None:
            parts.append('<span title="%s">no %s picture: %s</span>' % (html.escape(title), html.escape(title), html.escape(reason)))
        else:
            parts.append('<img alt="%s" title="%s" src="data:image/png;base64,%s">'
                         % (html.escape(title), html.escape(title), base64.b64encode(png).decode('ascii')))
    return '<td class="pics">%s</td>' % ''.join(parts)


def write_report(rows, models, outdir, sdm, ok_statuses, title='', up='', workers=2):
    """OUTDIR/report.html for the summary `rows` (run_batch's) of the model files `models` (in the
    same order), thumbnails drawn with `sdm` (`workers` at a time); written to a temporary name, then
    moved. Returns its path; raises OSError when it cannot be written."""
    fixed = ['name', 'status', 'error', 'seconds']
    figures = sorted({k for r in rows for k in r if k not in fixed and isinstance(r[k], (int, float)) and not isinstance(r[k], bool)
                      and k != 'exit_code'})
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        thumbs = list(pool.map(lambda rm: thumbnails(sdm, rm[0], rm[1], outdir, up), zip(rows, models)))
    head = ''.join('<th data-key="%s" data-numeric="%d">%s</th>' % (k, k in figures or k == 'seconds', html.escape(k.replace('_', ' ')))
                   for k in ['name', 'status', 'error', 'seconds'] + figures) + '<th data-key="pictures">pictures</th>'
    body = []
    failed = 0
    for r, t in zip(rows, thumbs):
        bad = r['status'] not in ok_statuses
        failed += bad
        cells = ['<td>%s</td>' % html.escape(r['name']),
                 '<td class="status">%s</td>' % html.escape(r['status']),
                 '<td class="error">%s</td>' % html.escape(r.get('error', '') or '')]
        cells += [cell(r.get('seconds'))] + [cell(r.get(k)) for k in figures] + [pictures(t)]
        body.append('<tr class="%s" data-name="%s">%s</tr>' % ('failed' if bad else 'ok', html.escape(r['name']), ''.join(cells)))
    summary = '%d models: %d finished, %d failed.' % (len(rows), len(rows) - failed, failed)
    page = PAGE % {'title': html.escape(title or os.path.basename(os.path.abspath(outdir))), 'thumb': THUMB, 'rows': len(rows),
                   'failed': failed, 'summary': summary, 'head': head, 'body': '\n'.join(body)}
    path = os.path.join(outdir, 'report.html')
    tmp = path + '.tmp'
    try:
        with open(tmp, 'w', encoding='utf-8') as f:
            f.write(page)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path



// The static bundle (docs/ARCHITECTURE.md, "Hosting"): `npm run dist` writes dist/ and `npm pack`
// packs the same files; each is served by Python's http.server, a plain
// static server that is not the project's, and opened in Chromium: the
// chapter page, a course page placed beside the bundle (embedding each
// widget with one script tag, under the CSP the README gives), and a
// course page on another origin (with and without the
// Access-Control-Allow-Origin header the README asks of such a host). Every
// one of the five widgets draws from the core, with no console errors.
// `npm pack --json` prints its JSON alone (the prepack build's progress
// goes to standard error), and the bundle's Custom Elements Manifest says
// exactly what the widgets declare.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import crypto from 'node:crypto';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { canvasColours, openPage, SCREENSHOTS, serveForeign, shutdown } from './harness.mjs';
import { manifestAttribute } from '../../scripts/lib/custom-elements.mjs';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const dist = path.join(root, 'dist');
let tmp; // this file's scratch directory
let tarball; // the packed package's path
let packed; // `npm pack --json`'s { status, stdout, stderr }
const servers = [];

/** What each widget shows once it has drawn, as a course page embeds it. */
const WIDGETS = {
  'cell-filter': {
    html: '<occgrid-cell-filter readings="ooff"></occgrid-cell-filter>',
    numbers: (w) => [...w.querySelectorAll('.cell-filter-table tbody tr')].map((tr) => Number(tr.dataset.l)),
    canvases: '.cell-filter-chart canvas',
  },
  'map-weaver': {
    html: '<occgrid-map-weaver laps="1" scans="40" autoplay="off"></occgrid-map-weaver>',
    numbers: (w) => (Number(w.dataset.scans) > 0
      ? [...w.querySelectorAll('.map-weaver-pane')].map((p) => Number.parseFloat(p.dataset.entropy)) : []),
    canvases: 'canvas.map-weaver-map',
  },
  'inverse-workbench': {
    html: '<occgrid-inverse-workbench reading="3"></occgrid-inverse-workbench>',
    numbers: (w) => (w.dataset.state === 'ready'
      ? [...w.querySelectorAll('.inverse-workbench-free, .inverse-workbench-l0')].map((o) => Number.parseFloat(o.textContent)) : []),
    canvases: 'canvas.inverse-workbench-image',
  },
  'sensor-fusion': {
    html: '<occgrid-sensor-fusion scans="20" autoplay="off"></occgrid-sensor-fusion>',
    numbers: (w) => [...w.querySelectorAll('.sensor-fusion-mean')].map((o) => Number.parseFloat(o.dataset.value)),
    canvases: 'canvas.sensor-fusion-map',
  },
  'doorway-trap': {
    html: '<occgrid-doorway-trap scans="3" flips="2" autoplay="off"></occgrid-doorway-trap>',
    numbers: (w) => (w.dataset.objective === undefined ? []
      : [w.dataset.objective, w.dataset.scan, w.dataset.doorCells, w.dataset.mapInDoorway].map(Number.parseFloat)),
    canvases: 'canvas.doorway-trap-canvas, canvas.doorway-trap-diagram',
  },
};

/** The CSP the README gives a course page that loads the widgets from `host`. */
const courseCsp = (host) => [
  "default-src 'none'",
  `script-src ${host} 'wasm-unsafe-eval'`,
  `style-src ${host}`,
  `connect-src ${host}`,
].join('; ');

/** An instructor's page: a heading, the five elements, one script tag each from `base`. */
function coursePage(base, csp) {
  const meta = csp ? `\n  <meta http-equiv="Content-Security-Policy" content="${csp}">` : '';
  return `<!doctype html>
<html lang="en">
<head>
  <meta charset="utf-8">${meta}
  <title>Week 9: occupancy grids</title>
</head>
<body>
  <h1>Week 9: occupancy grids</h1>
${Object.entries(WIDGETS).map(([name, w]) => `  <section>
    <script type="module" src="${base}widgets/${name}.js"></script>
    ${w.html}
  </section>`).join('\n')}
</body>
</html>
`;
}

/**
 * Starts Python's http.server on `dir` on a free loopback port (optionally
 * sending Access-Control-Allow-Origin: * and Cross-Origin-Resource-Policy:
 * cross-origin on every response) and resolves to its origin. Stopped in
 * `after`.
 */
function python(dir, { cors = false, corp = false } = {}) {
  const args = cors || corp
    ? ['-u', '-c', [
      'import functools, http.server, sys',
      'class H(http.server.SimpleHTTPRequestHandler):',
      '    def end_headers(self):',
      ...(cors ? ["        self.send_header('Access-Control-Allow-Origin', '*')"] : []),
      ...(corp ? ["        self.send_header('Cross-Origin-Resource-Policy', 'cross-origin')"] : []),
      '        super().end_headers()',
      's = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(H, directory=sys.argv[1]))',
      'print("Serving HTTP on 127.0.0.1 port %d" % s.server_address[1], flush=True)',
      's.serve_forever()',
    ].join('\n'), dir]
    : ['-u', '-m', 'http.server', '0', '--bind', '127.0.0.1', '--directory', dir];
  const child = spawn('python3', args, { stdio: ['ignore', 'pipe', 'pipe'] });
  servers.push(child);
  return new Promise((resolve, reject) => {
    let out = '';
    const seen = (chunk) => {
      out += chunk;
      const m = /Serving HTTP on \S+ port (\d+)/.exec(out);
      if (m) resolve(`http://127.0.0.1:${m[1]}`);
    };
    child.stdout.on('data', seen);
    child.stderr.on('data', (c) => { out += c; });
    child.once('error', reject);
    child.once('exit', (code) => reject(new Error(`python3 http.server exited (${code}): ${out}`)));
  });
}

/**
 * Opens `url` and checks that all five widgets draw: numbers from the core
 * in their readouts, pictures on their canvases, no console error. Returns
 * the URLs the page requested.
 */
async function checkFive(url, shot) {
  const { page: p, errors, close } = await openPage(url, { viewport: { width: 1100, height: 900 } });
  try {
    for (const [name, spec] of Object.entries(WIDGETS)) {
      const w = p.locator(`occgrid-${name}`);
      assert.equal(await w.count(), 1, `${url} has one occgrid-${name}`);
      await w.scrollIntoViewIfNeeded();
      // Polled (a course page's CSP rightly forbids evaluating code strings);
      // the deadline only stops a hang.
      // A widget shows its numbers, then draws them in a later frame: both awaited.
      let numbers = [];
      let c = [];
      const drawn = () => numbers.length >= 2 && numbers.every(Number.isFinite) && c.length >= 1 && c.every((n) => n > 2);
      for (const until = Date.now() + 60_000; Date.now() < until; await p.waitForTimeout(100)) {
        numbers = await w.evaluate(spec.numbers);
        c = await canvasColours(w, spec.canvases);
        if (drawn()) break;
      }
      assert.ok(numbers.length >= 2 && numbers.every(Number.isFinite), `occgrid-${name} shows numbers from the core: ${numbers}`);
      assert.ok(c.length >= 1 && c.every((n) => n > 2), `occgrid-${name} canvases hold pictures: ${c}`);
      // The widget's own stylesheet applies (found beside the module).
      assert.equal(await w.evaluate((el) => getComputedStyle(el).borderTopStyle), 'solid', `occgrid-${name} is styled`);
    }
    fs.mkdirSync(SCREENSHOTS, { recursive: true });
    await p.screenshot({ path: path.join(SCREENSHOTS, `${shot}.png`), fullPage: true });
    assert.deepEqual(errors, [], `${url}: no console errors`);
    return await p.evaluate(() => performance.getEntriesByType('resource').map((e) => e.name));
  } finally {
    await close();
  }
}

/** The hashed core files a bundle directory holds, checked against its manifest and loader. */
function checkBundle(dir) {
  const manifest = JSON.parse(fs.readFileSync(path.join(dir, 'occgrid-bundle.json'), 'utf8'));
  const pkg = fs.readdirSync(path.join(dir, 'pkg'));
  const wasm = pkg.filter((f) => f.endsWith('.wasm')).sort();
  // Two modules: the chapter's widgets, and real logs (loaded on demand).
  assert.deepEqual(wasm.map((f) => `pkg/${f}`), [manifest.wasm, manifest.logs.wasm].sort(), `two wasm files: ${pkg}`);
  const loader = fs.readFileSync(path.join(dir, 'widgets/lib/core.js'), 'utf8');
  for (const [stem, files] of [['occgrid', manifest], ['occgrid_logs', manifest.logs]]) {
    // The name carries the content's hash: another core is another URL.
    const bytes = fs.readFileSync(path.join(dir, files.wasm));
    const hash = new RegExp(`^pkg/${stem}_bg\\.([0-9a-f]{16})\\.wasm$`).exec(files.wasm)?.[1];
    assert.ok(hash, `hashed wasm name: ${files.wasm}`);
    assert.equal(crypto.createHash('sha256').update(bytes).digest('hex').slice(0, 16), hash);
    assert.ok(WebAssembly.validate(bytes), `${files.wasm} is a valid module`);
    const glue = fs.readFileSync(path.join(dir, files.glue));
    assert.ok(files.glue.startsWith(`pkg/${stem}.`), files.glue);
    assert.ok(files.glue.endsWith(`.${crypto.createHash('sha256').update(glue).digest('hex').slice(0, 16)}.js`), files.glue);
    assert.ok(loader.includes(`'../../${files.wasm}'`) && loader.includes(`'../../${files.glue}'`), `the loader names ${stem}'s hashed files`);
    assert.ok(!loader.includes(`${stem}_bg.wasm'`) && !loader.includes(`'../../pkg/${stem}.js'`), 'and no unhashed one');
  }
  // What the widgets import, at the place they import it from.
  for (const f of ['index.html', 'chapter.css', 'widgets/map-weaver.js', 'widgets/lib/occgrid.css', 'vendor/uplot/uPlot.esm.js', 'vendor/uplot/uPlot.min.css']) {
    assert.ok(fs.existsSync(path.join(dir, f)), `${f} is in the bundle`);
  }
  for (const f of manifest.files) assert.ok(fs.existsSync(path.join(dir, f)), `${f} listed and present`);
  // Relative URLs only: nothing in the page or the widgets starts at a host's root.
  for (const f of manifest.files.filter((x) => /\.(html|css)$/.test(x) || x.startsWith('widgets/'))) {
    const text = fs.readFileSync(path.join(dir, f), 'utf8');
    assert.doesNotMatch(text, /\b(?:src|href)\s*=\s*["']\/|\bfrom\s*['"]\/|import\(\s*['"]\/|url\(\s*['"]?\//, `${f} uses relative URLs`);
  }
  return manifest;
}

/** A course page beside a copy of `bundle`: DIR/occgrid/ and DIR/course.html. */
function besides(bundle, name) {
  const site = path.join(tmp, name);
  fs.cpSync(bundle, path.join(site, 'occgrid'), { recursive: true });
  fs.writeFileSync(path.join(site, 'course.html'), coursePage('occgrid/', courseCsp("'self'")));
  return site;
}

before(() => {
  tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'occgrid-dist-'));
  const run = spawnSync('npm', ['run', '--silent', 'dist'], { cwd: root, encoding: 'utf8' });
  assert.equal(run.status, 0, `npm run dist: ${run.stdout}${run.stderr}`);
  const pack = spawnSync('npm', ['pack', '--json', '--pack-destination', tmp], { cwd: root, encoding: 'utf8' });
  assert.equal(pack.status, 0, `npm pack: ${pack.stderr}`);
  packed = pack;
  // Read leniently here; the test below holds standard output to JSON alone.
  const info = JSON.parse(pack.stdout.slice(pack.stdout.indexOf('[')))[0];
  tarball = path.join(tmp, info.filename);
  const unpacked = path.join(tmp, 'unpacked');
  fs.mkdirSync(unpacked);
  const tar = spawnSync('tar', ['-xzf', tarball, '-C', unpacked], { encoding: 'utf8' });
  assert.equal(tar.status, 0, tar.stderr);
});

after(async () => {
  await shutdown();
  for (const child of servers) child.kill();
  if (tmp) fs.rmSync(tmp, { recursive: true, force: true });
});

test('npm pack --json prints only JSON on standard output; the prepack build’s progress goes to standard error', () => {
  const info = JSON.parse(packed.stdout);
  assert.ok(Array.isArray(info) && info.length === 1, packed.stdout.slice(0, 200));
  assert.equal(info[0].filename, path.basename(tarball));
  assert.ok(info[0].files.some((f) => f.path === 'dist/custom-elements.json'), 'the manifest is packed');
  assert.match(packed.stderr, /dist: wrote dist\//, 'the progress line is on standard error');
  // The same for the script on its own: nothing on standard output.
  const run = spawnSync('node', ['scripts/dist.mjs', '--out', path.join(tmp, 'quiet')], { cwd: root, encoding: 'utf8' });
  assert.equal(run.status, 0, run.stderr);
  assert.equal(run.stdout, '');
  assert.match(run.stderr, /^dist: wrote /m);
});

test('dist/ and the package carry a Custom Elements Manifest that says what each widget declares', async () => {
  const read = (dir) => JSON.parse(fs.readFileSync(path.join(dir, 'custom-elements.json'), 'utf8'));
  const manifest = read(dist);
  assert.deepEqual(read(path.join(tmp, 'unpacked/package/dist')), manifest, 'the package holds the same manifest');
  assert.ok(checkBundle(dist).files.includes('custom-elements.json'), 'listed in occgrid-bundle.json');
  assert.equal(manifest.schemaVersion, '2.1.0');
  const declared = manifest.modules.flatMap((m) => m.declarations.map((d) => ({ ...d, module: m.path, exports: m.exports })));
  // Each module path is a file of the bundle that defines the element.
  for (const d of declared) {
    assert.ok(fs.existsSync(path.join(dist, d.module)), d.module);
    assert.deepEqual(d.exports.find((e) => e.name === d.tagName)?.declaration, { name: d.name, module: d.module });
  }

  // The widgets' own declarations, as the page holds them once the core has
  // given its bounds and defaults (as each widget resolves them).
  const origin = await python(dist);
  const { page: p, errors, close } = await openPage(`${origin}/index.html`);
  try {
    const specs = await p.evaluate(async () => {
      const { loadCore } = await import(new URL('widgets/lib/core.js', location.href).href);
      const { core } = await loadCore();
      const k = core.constants();
      const tags = [...document.querySelectorAll('*')].map((e) => e.localName).filter((t, i, all) => t.startsWith('occgrid-') && all.indexOf(t) === i);
      return Object.fromEntries(tags.map((tag) => {
        const cls = customElements.get(tag);
        return [tag, {
          name: cls.name,
          attributes: Object.entries(cls.attributeSpec).map(([name, s]) => {
            const r = s.core ? { ...s, ...s.core(k) } : s;
            return { name, doc: r.doc, default: r.default, describe: r.type.describe };
          }),
        }];
      }));
    });
    assert.deepEqual(declared.map((d) => d.tagName).sort(), Object.keys(specs).sort(), 'one declaration per element of the page');
    for (const d of declared) {
      const spec = specs[d.tagName];
      assert.equal(d.name, spec.name, d.tagName);
      const want = spec.attributes.map((a) => manifestAttribute(a.name, { doc: a.doc, default: a.default, type: { describe: a.describe } }));
      assert.deepEqual(d.attributes, want, `${d.tagName}'s attributes`);
    }
    // A bad value is refused with the words the manifest gives.
    const clamp = declared.find((d) => d.tagName === 'occgrid-cell-filter').attributes.find((a) => a.name === 'clamp');
    await p.locator('occgrid-cell-filter').evaluate((el) => el.setAttribute('clamp', 'tight'));
    const alert = await p.locator('occgrid-cell-filter .occgrid-attribute-error').textContent();
    assert.ok(clamp.description.endsWith(`Expected: ${/\(expected (.*)\)$/.exec(alert)[1]}.`), `${clamp.description} | ${alert}`);
    assert.equal(errors.length, 1, errors.join('\n'));
  } finally {
    await close();
  }
});

test('npm run dist writes a self-contained bundle whose core is named by its content', () => {
  const manifest = checkBundle(dist);
  assert.ok(!fs.existsSync(path.join(dist, 'pkg/.gitignore')), 'no .gitignore from wasm-pack hides the core');
  // Each wasm is the one pkg/ holds, only renamed.
  assert.ok(fs.readFileSync(path.join(dist, manifest.wasm)).equals(fs.readFileSync(path.join(root, 'pkg/occgrid_bg.wasm'))));
  assert.ok(fs.readFileSync(path.join(dist, manifest.logs.wasm)).equals(fs.readFileSync(path.join(root, 'pkg/occgrid_logs_bg.wasm'))));
});

test('npm pack carries the same files as dist/, built wasm included', () => {
  const packed = path.join(tmp, 'unpacked/package/dist');
  const a = checkBundle(dist);
  const b = checkBundle(packed);
  assert.deepEqual(b, a, 'same manifest');
  for (const f of a.files) {
    assert.ok(fs.readFileSync(path.join(packed, f)).equals(fs.readFileSync(path.join(dist, f))), `${f} is the same file`);
  }
  const size = fs.statSync(tarball).size;
  console.log(`# ${path.basename(tarball)}: ${(size / 1024).toFixed(0)} KiB packed; core ${a.wasm}`);
  assert.ok(size > fs.statSync(path.join(dist, a.wasm)).size / 4, 'the tarball holds the wasm');
});

test('the chapter page served from dist/ by python3 -m http.server: all five widgets draw, the hashed core is what loads', async () => {
  const manifest = checkBundle(dist);
  const origin = await python(dist);
  const requested = await checkFive(`${origin}/index.html`, 'dist-chapter');
  assert.ok(requested.includes(`${origin}/${manifest.wasm}`), `the page fetched ${manifest.wasm}: ${requested.join(', ')}`);
  assert.ok(requested.includes(`${origin}/${manifest.glue}`), `and ${manifest.glue}`);
  assert.deepEqual(requested.filter((u) => /\/pkg\/occgrid(_logs)?(_bg)?\.(js|wasm)$/.test(u)), [], 'no unhashed core file');
  // The real-log module is not fetched by a page that opens no log.
  assert.deepEqual(requested.filter((u) => u.includes('/pkg/occgrid_logs')), [], 'no real-log module on load');
});

test('the bundle’s Map Weaver fetches the hashed real-log module when its real-log mode opens, and reads a log with it', async () => {
  const manifest = checkBundle(dist);
  const origin = await python(dist);
  const { page: p, errors, close } = await openPage(`${origin}/index.html`, { reducedMotion: 'reduce' });
  try {
    const w = p.locator('occgrid-map-weaver');
    await w.scrollIntoViewIfNeeded();
    const fetched = () => p.evaluate(() => performance.getEntriesByType('resource').map((e) => e.name).filter((u) => u.includes('/pkg/occgrid_logs')));
    await p.waitForFunction(() => Number(document.querySelector('occgrid-map-weaver')?.dataset.scans) >= 0, null, { timeout: 60_000 });
    assert.deepEqual(await fetched(), [], 'nothing of the log module before the mode opens');
    await w.getByLabel('Real log').check();
    const log = 'FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n'.repeat(5);
    await w.locator('.map-weaver-log input[type=file]').setInputFiles({ name: 'tiny.log', mimeType: 'text/plain', buffer: Buffer.from(log) });
    await p.waitForFunction(() => document.querySelector('.map-weaver-log')?.dataset.state === 'done', null, { timeout: 60_000 });
    assert.deepEqual((await fetched()).map((u) => new URL(u).pathname.slice(1)).sort(), [manifest.logs.glue, manifest.logs.wasm].sort());
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

test('a course page beside the bundle embeds all five widgets with one script tag each, under the README’s CSP', async () => {
  const origin = await python(besides(dist, 'site'));
  await checkFive(`${origin}/course.html`, 'dist-course');
});

test('the same from the unpacked npm pack tarball: the chapter page and a course page beside it', async () => {
  const packed = path.join(tmp, 'unpacked/package/dist');
  await checkFive(`${await python(packed)}/index.html`, 'pack-chapter');
  await checkFive(`${await python(besides(packed, 'site-pack'))}/course.html`, 'pack-course');
});

test('a course page on another origin: works when the bundle’s host sends Access-Control-Allow-Origin, fails without', async () => {
  const host = await python(dist, { cors: true });
  const foreign = await serveForeign({ '/course.html': coursePage(`${host}/`, courseCsp(host)) });
  try {
    await checkFive(`${foreign.origin}/course.html`, 'dist-cross-origin');
  } finally {
    await foreign.close();
  }
  // A plain static host without the header: the browser refuses the module.
  const plain = await python(dist);
  const bare = await serveForeign({ '/course.html': coursePage(`${plain}/`, courseCsp(plain)) });
  try {
    const { page: p, errors, close } = await openPage(`${bare.origin}/course.html`);
    await p.waitForLoadState('networkidle');
    assert.equal(await p.evaluate(() => customElements.get('occgrid-cell-filter')), undefined, 'no widget defined');
    assert.ok(errors.some((e) => /CORS|Access-Control-Allow-Origin/.test(e)), `a CORS error: ${errors.join(' | ')}`);
    await close();
  } finally {
    await bare.close();
  }
});

test('a cross-origin isolated course page: the stylesheets need Cross-Origin-Resource-Policy as well', async () => {
  const coep = { 'Cross-Origin-Embedder-Policy': 'require-corp' };
  const both = await python(dist, { cors: true, corp: true });
  const isolated = await serveForeign({ '/course.html': coursePage(`${both}/`, courseCsp(both)) }, { headers: coep });
  try {
    await checkFive(`${isolated.origin}/course.html`, 'dist-isolated');
  } finally {
    await isolated.close();
  }
  // With the CORS header alone the modules and the wasm load, the stylesheets (linked without CORS) do not.
  const cors = await python(dist, { cors: true });
  const bare = await serveForeign({ '/course.html': coursePage(`${cors}/`, courseCsp(cors)) }, { headers: coep });
  try {
    const { page: p, errors, close } = await openPage(`${bare.origin}/course.html`);
    await p.waitForLoadState('networkidle');
    assert.ok(errors.some((e) => /request failed: .*\/widgets\/lib\/occgrid\.css/.test(e)), `the stylesheet is refused: ${errors.join(' | ')}`);
    assert.notEqual(await p.locator('occgrid-cell-filter').evaluate((el) => getComputedStyle(el).borderTopStyle), 'solid', 'so the widget is unstyled');
    await close();
  } finally {
    await bare.close();
  }
});

test('npm run dist refuses bad arguments and never replaces a directory it did not write', () => {
  const other = path.join(tmp, 'notes');
  fs.mkdirSync(other);
  fs.writeFileSync(path.join(other, 'keep.txt'), 'mine');
  const r = spawnSync('node', ['scripts/dist.mjs', '--out', other], { cwd: root, encoding: 'utf8' });
  assert.equal(r.status, 1);
  assert.match(r.stderr, /is a non-empty directory that holds no occgrid-bundle\.json; not replacing it/);
  assert.equal(fs.readFileSync(path.join(other, 'keep.txt'), 'utf8'), 'mine');
  assert.deepEqual(fs.readdirSync(tmp).filter((f) => f.startsWith('notes.partial')), [], 'no partial bundle left behind');
  const bad = spawnSync('node', ['scripts/dist.mjs', '--outt', other], { cwd: root, encoding: 'utf8' });
  assert.equal(bad.status, 1);
  assert.match(bad.stderr, /unknown argument: "--outt"/);
  const empty = spawnSync('node', ['scripts/dist.mjs', '--out'], { cwd: root, encoding: 'utf8' });
  assert.equal(empty.status, 1);
  assert.match(empty.stderr, /--out needs a directory/);
  const self = spawnSync('node', ['scripts/dist.mjs', '--out', root], { cwd: root, encoding: 'utf8' });
  assert.equal(self.status, 1);
  assert.match(self.stderr, /would contain the project itself/);
});

// Writes dist/: everything the chapter page and the widgets need, laid out so
// that any plain static server (a university web space, GitHub Pages, an LMS
// file area, a package CDN) serves it as it is, under any path.
//
//   dist/index.html, chapter.css, favicon.svg   the chapter page (www/)
//   dist/widgets/                               the widgets (widgets/)
//   dist/pkg/occgrid.HASH.js, occgrid_bg.HASH.wasm  the core: the chapter's widgets (pkg/)
//   dist/pkg/occgrid_logs.HASH.js, occgrid_logs_bg.HASH.wasm  and real logs, loaded on demand
//   dist/vendor/uplot/                          uPlot (node_modules/uplot/dist/)
//   dist/datasets/README.md                     an empty list of real logs, for a host to fill
//   dist/custom-elements.json                   the widgets' Custom Elements Manifest, for editors
//   dist/occgrid-bundle.json                    what was written, and from which core
//
// The core's files carry a hash of their content in their names and the
// loader in dist/widgets/lib/core.js names them, so a browser or a CDN that
// caches the old core never pairs it with a new page: a new core is a new URL.
// Every URL inside the bundle is relative; the run fails if one is not, or if
// a file the page or a widget imports is missing.
//
// The manifest is generated from the attribute declarations each widget
// module holds (scripts/lib/custom-elements.mjs), so it says what the widgets
// check, and nothing else.
//
// Usage: node scripts/dist.mjs [--out DIR]     (npm run dist)
// Builds pkg/ first (scripts/build.sh) when it is missing or older than the
// Rust sources. Progress goes to standard error: standard output stays free
// for what a caller reads there (`npm pack --json`, whose prepack runs this).
import fs from 'node:fs';
import path from 'node:path';
import crypto from 'node:crypto';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { customElementsManifest } from './lib/custom-elements.mjs';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
/** Written into every bundle; a directory without it is never replaced. */
const MARKER = 'occgrid-bundle.json';
/** The widgets' Custom Elements Manifest, at the bundle's root. */
const ELEMENTS = 'custom-elements.json';
/**
 * The core's two wasm modules (scripts/build.sh), by their file stems in
 * pkg/: widgets/lib/core.js loads each by `../../pkg/STEM.js` and
 * `../../pkg/STEM_bg.wasm`, specifiers rewritten in the bundle.
 */
const CORE_MODULES = ['occgrid', 'occgrid_logs'];
const UPLOT_FILES = ['uPlot.esm.js', 'uPlot.min.css'];
/**
 * The bundle's datasets/README.md: the real-log panel reads the logs to
 * offer from the table of a README.md in datasets/ beside widgets/. A
 * bundle carries no logs, and says so here, so that the panel's question
 * is answered (no 404) and its menu stays hidden until a host adds logs.
 */
const EMPTY_DATASETS = `# Real 2-D laser logs

This bundle carries none. To offer logs in Map Weaver's real-log menu, put
CARMEN logs (\`.log\` or \`.log.gz\`) in this folder and list each as a row
of this table: its file name, the place, and its number of FLASER scans.

| file | place | FLASER scans |
| --- | --- | --- |
`;

class DistError extends Error {}

function parseArgs(argv) {
  let out = path.join(root, 'dist');
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--out') {
      const v = argv[++i];
      if (!v) throw new DistError('--out needs a directory (e.g. --out /tmp/occgrid)');
      out = path.resolve(v);
    } else if (a.startsWith('--out=')) {
      const v = a.slice('--out='.length);
      if (!v) throw new DistError('--out needs a directory (e.g. --out=/tmp/occgrid)');
      out = path.resolve(v);
    } else {
      throw new DistError(`unknown argument: ${JSON.stringify(a)} (usage: node scripts/dist.mjs [--out DIR])`);
    }
  }
  return { out };
}

/** Newest modification time of the files under `p` (0 when absent). */
function newest(p) {
  let st;
  try { st = fs.statSync(p); } catch { return 0; }
  if (!st.isDirectory()) return st.mtimeMs;
  let t = 0;
  for (const e of fs.readdirSync(p)) t = Math.max(t, newest(path.join(p, e)));
  return t;
}

/** Makes sure pkg/ holds a core built from the current sources. */
function ensureCore() {
  const files = CORE_MODULES.flatMap((stem) => [path.join(root, `pkg/${stem}_bg.wasm`), path.join(root, `pkg/${stem}.js`)]);
  const built = Math.min(...files.map(newest));
  const sources = Math.max(...['src', 'Cargo.toml', 'Cargo.lock'].map((p) => newest(path.join(root, p))));
  if (built > 0 && (sources === 0 || built >= sources)) return;
  console.error(built === 0
    ? 'dist: pkg/ has no built core yet; building it (bash scripts/build.sh)'
    : 'dist: pkg/ is older than the Rust sources; rebuilding it (bash scripts/build.sh)');
  // The build's own output to standard error as well.
  const r = spawnSync('bash', ['scripts/build.sh'], { cwd: root, stdio: ['ignore', 2, 2] });
  if (r.status !== 0 || !files.every((f) => fs.existsSync(f))) {
    throw new DistError('building the wasm core failed (see above). It needs the Rust toolchain and wasm-pack: '
      + 'run `bash scripts/setup.sh`, then `npm run build`, then `npm run dist` again.');
  }
}

function hashOf(buf) {
  return crypto.createHash('sha256').update(buf).digest('hex').slice(0, 16);
}

/** Copies a directory tree, leaving out dotfiles (editor and VCS litter). */
function copyTree(from, to, files) {
  fs.mkdirSync(to, { recursive: true });
  for (const e of fs.readdirSync(from, { withFileTypes: true })) {
    if (e.name.startsWith('.')) continue;
    const a = path.join(from, e.name);
    const b = path.join(to, e.name);
    if (e.isDirectory()) copyTree(a, b, files);
    else if (e.isFile()) { fs.copyFileSync(a, b); files.push(b); }
  }
}

/** Replaces `from` by `to` in `text`, which must hold it exactly once. */
function replaceOnce(text, from, to, file) {
  const n = text.split(from).length - 1;
  if (n !== 1) throw new DistError(`${file}: expected ${JSON.stringify(from)} exactly once, found it ${n} times`);
  return text.replace(from, () => to);
}

/**
 * The URLs each text file of the bundle names: in HTML src/href attributes,
 * in JS static and dynamic imports and `new URL('...', import.meta.url)`, in
 * CSS url(). Returns `[url, file]` pairs.
 */
function referencedUrls(dir, files) {
  const patterns = {
    '.html': [/\b(?:src|href)\s*=\s*"([^"]*)"/g, /\b(?:src|href)\s*=\s*'([^']*)'/g],
    '.js': [/\bfrom\s*['"]([^'"]+)['"]/g, /\bimport\s*\(\s*['"]([^'"]+)['"]\s*\)/g, /^\s*import\s*['"]([^'"]+)['"]/gm,
      /new URL\(\s*['"]([^'"]+)['"]\s*,\s*import\.meta\.url\s*\)/g],
    '.css': [/url\(\s*['"]?([^'")]+)['"]?\s*\)/g, /@import\s+['"]([^'"]+)['"]/g],
  };
  const out = [];
  for (const f of files) {
    const list = patterns[path.extname(f)];
    if (!list) continue;
    const text = fs.readFileSync(f, 'utf8');
    for (const re of list) for (const m of text.matchAll(re)) out.push([m[1], f]);
  }
  return out;
}

/** Fails on absolute URLs and on relative ones that point at nothing in the bundle. */
function checkUrls(dir, files) {
  const problems = [];
  for (const [url, file] of referencedUrls(dir, files)) {
    const where = path.relative(dir, file);
    if (/^(?:data|blob|mailto):/i.test(url) || url.startsWith('#')) continue;
    if (/^[a-z][a-z0-9+.-]*:/i.test(url) || url.startsWith('//')) {
      problems.push(`${where}: absolute URL ${JSON.stringify(url)} (the bundle must work from any host)`);
      continue;
    }
    if (url.startsWith('/')) {
      problems.push(`${where}: root-relative URL ${JSON.stringify(url)} (the bundle must work under any path)`);
      continue;
    }
    const clean = url.split(/[?#]/)[0];
    // A directory (the optional ../datasets/ beside widgets/) is looked up at run time.
    if (clean === '' || clean.endsWith('/')) continue;
    const target = path.resolve(path.dirname(file), clean);
    if (!target.startsWith(dir + path.sep)) {
      problems.push(`${where}: ${JSON.stringify(url)} points outside the bundle`);
    } else if (!fs.existsSync(target)) {
      problems.push(`${where}: ${JSON.stringify(url)} names a file the bundle does not have`);
    }
  }
  if (problems.length) throw new DistError(`the bundle is not self-contained:\n  ${problems.join('\n  ')}`);
}

/** Removes `out` only if it is absent, empty, or a bundle this script wrote. */
function clearOut(out) {
  if (!fs.existsSync(out)) return;
  if (!fs.statSync(out).isDirectory()) throw new DistError(`--out ${out} exists and is not a directory`);
  const entries = fs.readdirSync(out);
  if (entries.length > 0 && !entries.includes(MARKER)) {
    throw new DistError(`--out ${out} is a non-empty directory that holds no ${MARKER}; not replacing it`);
  }
  fs.rmSync(out, { recursive: true, force: true });
}

function build({ out }) {
  if (out === root || root.startsWith(out + path.sep)) throw new DistError(`--out ${out} would contain the project itself`);
  for (const f of UPLOT_FILES) {
    if (!fs.existsSync(path.join(root, 'node_modules/uplot/dist', f))) {
      throw new DistError(`node_modules/uplot/dist/${f} is missing: run \`npm ci\` (or \`npm install\`) first`);
    }
  }
  ensureCore();

  // Written beside `out` and moved into place at the end, so a failed run
  // leaves the previous bundle as it was.
  const stage = `${out}.partial-${process.pid}`;
  fs.rmSync(stage, { recursive: true, force: true });
  const files = [];
  try {
    copyTree(path.join(root, 'www'), stage, files);
    copyTree(path.join(root, 'widgets'), path.join(stage, 'widgets'), files);
    fs.mkdirSync(path.join(stage, 'datasets'));
    fs.writeFileSync(path.join(stage, 'datasets/README.md'), EMPTY_DATASETS);
    files.push(path.join(stage, 'datasets/README.md'));

    const pkg = path.join(stage, 'pkg');
    fs.mkdirSync(pkg, { recursive: true });
    // Code the glue imports from the crate's JS snippets, if any, goes along.
    const snippets = path.join(root, 'pkg/snippets');
    if (fs.existsSync(snippets)) copyTree(snippets, path.join(pkg, 'snippets'), files);
    const loader = path.join(stage, 'widgets/lib/core.js');
    let text = fs.readFileSync(loader, 'utf8');
    const hashed = {};
    for (const stem of CORE_MODULES) {
      const wasmBytes = fs.readFileSync(path.join(root, `pkg/${stem}_bg.wasm`));
      const wasmName = `${stem}_bg.${hashOf(wasmBytes)}.wasm`;
      fs.writeFileSync(path.join(pkg, wasmName), wasmBytes);
      files.push(path.join(pkg, wasmName));
      // The glue's own fallback (used by a bare `init()`) names the same file.
      const glueText = replaceOnce(fs.readFileSync(path.join(root, `pkg/${stem}.js`), 'utf8'),
        `'${stem}_bg.wasm'`, `'${wasmName}'`, `pkg/${stem}.js`);
      const glueName = `${stem}.${hashOf(glueText)}.js`;
      fs.writeFileSync(path.join(pkg, glueName), glueText);
      files.push(path.join(pkg, glueName));
      text = replaceOnce(text, `'../../pkg/${stem}.js'`, `'../../pkg/${glueName}'`, 'widgets/lib/core.js');
      text = replaceOnce(text, `'../../pkg/${stem}_bg.wasm'`, `'../../pkg/${wasmName}'`, 'widgets/lib/core.js');
      hashed[stem] = { wasm: `pkg/${wasmName}`, glue: `pkg/${glueName}` };
    }
    fs.writeFileSync(loader, text);
    const { wasm: wasmPath, glue: gluePath } = hashed.occgrid;

    const vendor = path.join(stage, 'vendor/uplot');
    fs.mkdirSync(vendor, { recursive: true });
    for (const f of [...UPLOT_FILES, '../LICENSE']) {
      const from = path.join(root, 'node_modules/uplot/dist', f);
      if (!fs.existsSync(from)) continue;
      const to = path.join(vendor, path.basename(f));
      fs.copyFileSync(from, to);
      files.push(to);
    }

    // Our own files; vendored and generated code is left as it is.
    checkUrls(stage, files.filter((f) => !/^(?:pkg|vendor)\//.test(path.relative(stage, f).split(path.sep).join('/'))));

    const elements = path.join(stage, ELEMENTS);
    fs.writeFileSync(elements, JSON.stringify(customElementsManifest(stage, { glue: gluePath, wasm: wasmPath }), null, 2) + '\n');
    files.push(elements);

    const version = JSON.parse(fs.readFileSync(path.join(root, 'package.json'), 'utf8')).version;
    const manifest = {
      name: 'occgrid',
      version,
      wasm: wasmPath,
      glue: gluePath,
      logs: hashed.occgrid_logs,
      files: files.map((f) => path.relative(stage, f).split(path.sep).join('/')).sort(),
    };
    fs.writeFileSync(path.join(stage, MARKER), JSON.stringify(manifest, null, 2) + '\n');

    clearOut(out);
    fs.renameSync(stage, out);
    const bytes = files.reduce((a, f) => a + fs.statSync(path.join(out, path.relative(stage, f))).size, 0);
    console.error(`dist: wrote ${path.relative(process.cwd(), out) || '.'}/ (${files.length + 1} files, ${(bytes / 1024).toFixed(0)} KiB; core ${manifest.wasm})`);
    return manifest;
  } catch (e) {
    fs.rmSync(stage, { recursive: true, force: true });
    throw e;
  }
}

try {
  build(parseArgs(process.argv.slice(2)));
} catch (e) {
  if (!(e instanceof DistError)) throw e;
  console.error(`dist: ${e.message}`);
  process.exit(1);
}

// Serves the chapter page: www/ at /, the widgets and the wasm package at
// /widgets/ and /pkg/, uPlot at /vendor/uplot/, and ../shared/datasets/ at
// /datasets/ when it exists. Every response carries CORS headers so that an
// instructor's page on another origin can import a widget from here.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import sirv from 'sirv';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');

/** Content-Security-Policy the page is written to work under. */
export const CSP = "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; style-src 'self'; img-src 'self' data: blob:; connect-src 'self'";

function mounts() {
  const opts = { dev: true, etag: true, dotfiles: false };
  const list = [
    ['/widgets/', sirv(path.join(root, 'widgets'), opts)],
    ['/pkg/', sirv(path.join(root, 'pkg'), opts)],
    ['/vendor/uplot/', sirv(path.join(root, 'node_modules/uplot/dist'), opts)],
  ];
  const datasets = path.resolve(root, '../shared/datasets');
  if (fs.existsSync(datasets)) list.push(['/datasets/', sirv(datasets, opts)]);
  const tests = path.join(root, 'tests/browser/fixtures');
  if (fs.existsSync(tests)) list.push(['/test-fixtures/', sirv(tests, opts)]);
  list.push(['/', sirv(path.join(root, 'www'), { ...opts, single: false })]);
  return list;
}

/**
 * sirv takes `x.log.gz` for a precompressed `x.log` and sends it with
 * `Content-Encoding: gzip`, so a browser would hand the page (or a download)
 * decompressed text under a `.gz` name. A log file is served as the gzip
 * file it is.
 */
function keepCompressed(res) {
  const writeHead = res.writeHead.bind(res);
  res.writeHead = (code, headers = {}) => {
    delete headers['Content-Encoding'];
    headers['Content-Type'] = 'application/gzip';
    res.removeHeader('Content-Encoding');
    return writeHead(code, headers);
  };
}

/** Creates (does not start) the server. */
export function createServer() {
  const list = mounts();
  return http.createServer((req, res) => {
    res.setHeader('Access-Control-Allow-Origin', '*');
    res.setHeader('Cross-Origin-Resource-Policy', 'cross-origin');
    res.setHeader('Content-Security-Policy', CSP);
    const url = new URL(req.url, 'http://localhost');
    const mount = list.find(([prefix]) => url.pathname.startsWith(prefix));
    const notFound = () => {
      res.statusCode = 404;
      res.setHeader('Content-Type', 'text/plain; charset=utf-8');
      res.end(`Not found: ${url.pathname}\n`);
    };
    if (!mount) return notFound();
    const [prefix, handler] = mount;
    if (url.pathname.endsWith('.gz')) keepCompressed(res);
    // Hand the mounted handler a path relative to its own root.
    req.url = '/' + req.url.slice(prefix.length);
    handler(req, res, notFound);
  });
}

/** Starts the server on `port` (0 = any free port); resolves to the port. */
export function listen(port) {
  const server = createServer();
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, '127.0.0.1', () => resolve({ server, port: server.address().port }));
  });
}

if (process.argv[1] && fileURLToPath(import.meta.url) === path.resolve(process.argv[1])) {
  const port = Number(process.env.PORT || 8080);
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`invalid PORT: ${process.env.PORT} (expected a whole number from 0 to 65535)`);
    process.exit(2);
  }
  if (!fs.existsSync(path.join(root, 'pkg/occgrid_bg.wasm'))) {
    console.error('pkg/ is missing: run `npm start` (or `npm run build`) first.');
    process.exit(1);
  }
  const { port: p } = await listen(port);
  console.log(`occgrid chapter page: http://localhost:${p}/`);
}

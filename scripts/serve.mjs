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

// sirv's dev mode looks each file up on disk per request. Without it sirv
// lists the files once at startup and answers from that list, sizes and
// dates included: a pkg/ rebuilt while the server runs would then be sent
// with the old Content-Length (cut short or padded), and a pkg/ built after
// the server started would not be served at all. Dev mode does not apply
// `dotfiles: false`, so dotfiles are refused before sirv sees the request
// (see `requestPath`).
function mounts({ fixtures }) {
  const opts = { dev: true, etag: true, dotfiles: false };
  const list = [
    ['/widgets/', sirv(path.join(root, 'widgets'), opts)],
    ['/pkg/', sirv(path.join(root, 'pkg'), opts)],
    ['/vendor/uplot/', sirv(path.join(root, 'node_modules/uplot/dist'), opts)],
  ];
  const datasets = path.resolve(root, '../shared/datasets');
  if (fs.existsSync(datasets)) list.push(['/datasets/', sirv(datasets, opts)]);
  // The browser tests' own pages; never part of the server readers run.
  if (fixtures) list.push(['/test-fixtures/', sirv(path.join(root, 'tests/browser/fixtures'), opts)]);
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

/** A request the server refuses: the status and a line saying why. */
class Refusal extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

/**
 * The decoded path segments of a request target, checked. The target is
 * taken as the path it must be (`new URL` would read `//host:port/` as an
 * authority and throw on a bad port). Refused: a target that is neither a
 * path nor an http URL, an empty segment, bad percent-encoding, a NUL byte, and any segment starting with a
 * dot, which covers `..` (also as `%2e%2e`), `.git` and every other
 * dotfile or dot-directory at any depth.
 */
function requestPath(target) {
  let raw;
  if (target.startsWith('/')) raw = target.split(/[?#]/, 1)[0];
  else {
    // The absolute form (`GET http://host/path`), which HTTP/1.1 servers
    // must accept; `new URL` is asked only here, and may refuse.
    let url;
    try {
      url = new URL(target);
    } catch {
      throw new Refusal(400, 'Bad request target: neither a path nor a URL');
    }
    if (url.protocol !== 'http:' && url.protocol !== 'https:') throw new Refusal(400, 'Bad request target: not an http URL');
    raw = url.pathname;
  }
  let decoded;
  try {
    decoded = decodeURIComponent(raw);
  } catch {
    throw new Refusal(400, 'Bad request target: malformed percent-encoding');
  }
  if (decoded.includes('\0')) throw new Refusal(400, 'Bad request target: NUL byte');
  const segments = decoded.split('/').slice(1);
  // `//x` is no file's path (and what `new URL` misreads as a host).
  if (segments.slice(0, -1).includes('')) throw new Refusal(400, 'Bad request target: empty path segment');
  if (segments.some((s) => s.startsWith('.'))) throw new Refusal(404, 'Not found');
  return segments;
}

/**
 * The byte range a request asks for, read here instead of by sirv. sirv
 * reads the end with `parseInt(end) || size - 1`, so `bytes=0-0` (the
 * first byte) came back as the whole file under `Content-Range: bytes
 * 0-263/264`, and it hands a reversed or huge range to
 * `fs.createReadStream` unchecked (which throws there, after the status
 * line went out). One `bytes=START-END` or `bytes=START-` range is
 * served: `{ start, end }`, `end` Infinity for "to the end". Anything else
 * (suffix ranges, several ranges, other units, garbage) is ignored, as
 * HTTP allows: null, and the whole file is sent. The header is taken off
 * the request either way, so sirv always answers with the whole file,
 * which `serveRange` cuts to the range.
 */
function takeRange(req) {
  const header = req.headers.range;
  delete req.headers.range;
  if (header === undefined) return null;
  const m = /^bytes=(\d+)-(\d*)$/.exec(header.trim());
  if (!m) return null;
  return { start: Number(m[1]), end: m[2] === '' ? Infinity : Number(m[2]) };
}

/**
 * Turns sirv's whole-file answer into the answer to `range`: 206 with the
 * bytes asked for (the end cut at the file's end), or 416 with the file's
 * size when the range starts past the end or ends before it starts. sirv
 * writes the head, then pipes a read stream of the whole file into `res`;
 * that stream is swapped for one of the range. Any other answer (304, 404)
 * goes out as sirv wrote it.
 */
function serveRange(res, range) {
  let slice = null; // the bytes to send once the head said 206; 'none' after a 416
  const writeHead = res.writeHead.bind(res);
  res.writeHead = (code, headers = {}) => {
    const size = Number(headers['Content-Length']);
    if (code !== 200 || !Number.isSafeInteger(size)) return writeHead(code, headers);
    if (range.start >= size || range.end < range.start) {
      slice = 'none';
      return writeHead(416, { ...headers, 'Content-Range': `bytes */${size}`, 'Content-Length': 0 });
    }
    slice = { start: range.start, end: Math.min(range.end, size - 1) };
    return writeHead(206, {
      ...headers,
      'Content-Range': `bytes ${slice.start}-${slice.end}/${size}`,
      'Content-Length': slice.end - slice.start + 1,
      'Accept-Ranges': 'bytes',
    });
  };
  let part = null;
  res.on('pipe', (source) => {
    if (!slice || source === part) return;
    source.unpipe(res);
    source.destroy();
    if (slice === 'none') {
      res.end();
      return;
    }
    part = fs.createReadStream(source.path, slice);
    part.on('error', () => res.destroy());
    part.pipe(res);
  });
}

function answer(res, status, message) {
  if (res.headersSent) {
    res.destroy();
    return;
  }
  res.statusCode = status;
  res.setHeader('Content-Type', 'text/plain; charset=utf-8');
  res.end(`${message}\n`);
}

/**
 * Creates (does not start) the server. `fixtures: true` also serves
 * tests/browser/fixtures/ at /test-fixtures/ (the browser tests' pages).
 */
export function createServer({ fixtures = false } = {}) {
  const list = mounts({ fixtures });
  const handle = (req, res) => {
    res.setHeader('Access-Control-Allow-Origin', '*');
    res.setHeader('Cross-Origin-Resource-Policy', 'cross-origin');
    res.setHeader('Content-Security-Policy', CSP);
    res.setHeader('X-Content-Type-Options', 'nosniff');
    if (req.method !== 'GET' && req.method !== 'HEAD') {
      res.setHeader('Allow', 'GET, HEAD');
      throw new Refusal(405, `Method not allowed: ${req.method}`);
    }
    const segments = requestPath(req.url);
    const pathname = '/' + segments.join('/');
    const mount = list.find(([prefix]) => pathname.startsWith(prefix));
    const notFound = () => answer(res, 404, `Not found: ${pathname}`);
    if (!mount) return notFound();
    const [prefix, handler] = mount;
    const range = takeRange(req);
    if (range) serveRange(res, range);
    if (pathname.endsWith('.gz')) keepCompressed(res);
    // A file that vanishes or cannot be read between sirv's stat and its
    // read (pkg/ being rebuilt, a socket or fifo in a served folder) makes
    // the read stream sirv pipes into the response fail; without a
    // listener that error would end the process.
    res.on('pipe', (source) => source.on('error', () => res.destroy()));
    // Hand the mounted handler the checked path relative to its own root,
    // encoded again so that sirv's own decoding yields these same segments.
    const inner = segments.slice(prefix.split('/').length - 2);
    req.url = '/' + inner.map(encodeURIComponent).join('/');
    handler(req, res, notFound);
  };
  return http.createServer((req, res) => {
    try {
      handle(req, res);
    } catch (e) {
      if (e instanceof Refusal) answer(res, e.status, e.message);
      else {
        // The last resort: the request fails, the server carries on.
        console.error(`serve: ${req.method} ${String(req.url).slice(0, 200)}: ${e && e.stack ? e.stack : e}`);
        answer(res, 500, 'Internal server error');
      }
    }
  });
}

/**
 * Starts the server on `port` (0 = any free port) with `options` (those of
 * `createServer`); resolves to `{ server, port }`.
 */
export function listen(port, options = {}) {
  const server = createServer(options);
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
  if (!['occgrid_bg.wasm', 'occgrid_logs_bg.wasm'].every((f) => fs.existsSync(path.join(root, 'pkg', f)))) {
    console.error('pkg/ is missing: run `npm start` (or `npm run build`) first.');
    process.exit(1);
  }
  const { port: p } = await listen(port);
  console.log(`occgrid chapter page: http://localhost:${p}/`);
}

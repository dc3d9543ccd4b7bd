// The project's server (scripts/serve.mjs) under hostile requests, sent raw
// over node:net so that nothing between the test and the server tidies them
// up: a request target `new URL` cannot parse, reversed and out-of-range
// byte ranges, garbage, a huge URL, path traversal (plain and encoded),
// dotfiles, the test pages, a file that cannot be read. The server runs in
// a child process, so that a request that would end it shows as the child
// having exited instead of taking the test runner down with it. Every
// response carries `X-Content-Type-Options: nosniff`, and after 1,000
// malformed requests the server still answers.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const SERVE = pathToFileURL(path.join(root, 'scripts/serve.mjs')).href;
const STATE_JS = fs.readFileSync(path.join(root, 'widgets/lib/state.js'));

/** Starts serve.mjs's `listen(0, options)` in a child; resolves to `{ port, child, stderr() }`. */
function startServer(options = {}) {
  const code = `const m = await import(${JSON.stringify(SERVE)});
const { port } = await m.listen(0, ${JSON.stringify(options)});
console.log('PORT ' + port);`;
  const child = spawn(process.execPath, ['--input-type=module', '-e', code], { stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  child.stderr.on('data', (d) => { err += d; });
  return new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d) => {
      out += d;
      const m = /PORT (\d+)/.exec(out);
      if (m) resolve({ port: Number(m[1]), child, stderr: () => err });
    });
    child.once('exit', (c) => reject(new Error(`server exited (${c}) before listening: ${err}`)));
  });
}

/**
 * Sends `raw` bytes on a fresh connection to 127.0.0.1:port and resolves to
 * the parsed response `{ status, headers, body }` (status null when the
 * server closed the connection without answering). A connection that stays
 * silent for 10 s is a hang and fails the request.
 */
function rawRequest(port, raw) {
  return new Promise((resolve, reject) => {
    const chunks = [];
    const socket = net.connect(port, '127.0.0.1');
    socket.setTimeout(10_000, () => {
      socket.destroy();
      reject(new Error(`no answer to ${JSON.stringify(raw.slice(0, 80))}`));
    });
    socket.on('data', (d) => chunks.push(d));
    socket.on('error', () => {}); // a reset is a closed connection; judged below
    socket.on('close', () => {
      const text = Buffer.concat(chunks);
      const split = text.indexOf('\r\n\r\n');
      if (split < 0) return resolve({ status: null, headers: {}, body: Buffer.alloc(0) });
      const [statusLine, ...lines] = text.subarray(0, split).toString('latin1').split('\r\n');
      const headers = {};
      for (const line of lines) {
        const i = line.indexOf(':');
        headers[line.slice(0, i).trim().toLowerCase()] = line.slice(i + 1).trim();
      }
      resolve({ status: Number(statusLine.split(' ')[1]), headers, body: text.subarray(split + 4) });
    });
    // Not `end`: a client that half-closes its side gets its streamed
    // response cut by Node's http server. Every request here asks for
    // `Connection: close`, or is one the server drops.
    socket.write(raw);
  });
}

/** A GET request for `target` (sent as is), with extra header lines. */
const get = (target, ...headers) =>
  `GET ${target} HTTP/1.1\r\nHost: 127.0.0.1\r\n${headers.map((h) => `${h}\r\n`).join('')}Connection: close\r\n\r\n`;

let plain; // the server as the README runs it
let withFixtures; // the server the browser tests run

before(async () => {
  [plain, withFixtures] = await Promise.all([startServer(), startServer({ fixtures: true })]);
});

after(() => {
  for (const s of [plain, withFixtures]) if (s && s.child.exitCode === null) s.child.kill();
});

function assertAlive(server) {
  assert.equal(server.child.exitCode, null, `the server exited: ${server.stderr()}`);
}

test('a request target that `new URL` cannot parse gets 400 and the server stays up', async () => {
  for (const target of ['//x:99999/', '//x:99999/widgets/lib/state.js', '//[::1/', 'http://x:99999/']) {
    const r = await rawRequest(plain.port, get(target));
    assertAlive(plain);
    assert.equal(r.status, 400, `${target} → ${r.status}`);
    assert.equal(r.headers['x-content-type-options'], 'nosniff');
  }
  const ok = await rawRequest(plain.port, get('/widgets/lib/state.js'));
  assert.equal(ok.status, 200);
});

test('malformed percent-encoding and NUL bytes get 400', async () => {
  for (const target of ['/widgets/%E0%A4%A', '/widgets/%zz', '/widgets/lib/state.js%00.png']) {
    const r = await rawRequest(plain.port, get(target));
    assertAlive(plain);
    assert.equal(r.status, 400, `${target} → ${r.status}`);
  }
});

test('a reversed byte range gets 416 with the file size and the server stays up', async () => {
  const r = await rawRequest(plain.port, get('/widgets/lib/state.js', 'Range: bytes=100-50'));
  assertAlive(plain);
  assert.equal(r.status, 416);
  assert.equal(r.headers['content-range'], `bytes */${STATE_JS.length}`);
});

test('a byte range past the end gets 416; one reaching past it is cut at the end', async () => {
  const past = await rawRequest(plain.port, get('/widgets/lib/state.js', `Range: bytes=${STATE_JS.length + 10}-`));
  assertAlive(plain);
  assert.equal(past.status, 416);
  assert.equal(past.headers['content-range'], `bytes */${STATE_JS.length}`);

  const huge = await rawRequest(plain.port, get('/widgets/lib/state.js', 'Range: bytes=99999999999999999999999-'));
  assertAlive(plain);
  assert.equal(huge.status, 416);

  // An end beyond any safe integer made fs.createReadStream throw after
  // the status line was sent.
  const tail = await rawRequest(plain.port, get('/widgets/lib/state.js', 'Range: bytes=10-99999999999999999999999'));
  assertAlive(plain);
  assert.equal(tail.status, 206);
  assert.equal(tail.headers['content-range'], `bytes 10-${STATE_JS.length - 1}/${STATE_JS.length}`);
  assert.deepEqual(tail.body, STATE_JS.subarray(10));

  const part = await rawRequest(plain.port, get('/widgets/lib/state.js', 'Range: bytes=3-9'));
  assert.equal(part.status, 206);
  assert.deepEqual(part.body, STATE_JS.subarray(3, 10));
});

test('a one-byte range is one byte: the first, a middle one, the last (sirv read an end of 0 as no end)', async () => {
  const favicon = fs.readFileSync(path.join(root, 'www/favicon.svg'));
  for (const [target, file] of [['/widgets/lib/state.js', STATE_JS], ['/favicon.svg', favicon]]) {
    for (const at of [0, 5, file.length - 1]) {
      const r = await rawRequest(plain.port, get(target, `Range: bytes=${at}-${at}`));
      assertAlive(plain);
      assert.equal(r.status, 206, `${target} byte ${at} → ${r.status}`);
      assert.equal(r.headers['content-range'], `bytes ${at}-${at}/${file.length}`);
      assert.equal(r.headers['content-length'], '1');
      assert.deepEqual(r.body, file.subarray(at, at + 1), `${target} byte ${at}`);
    }
  }
  // HEAD answers the same head and no body.
  const head = await rawRequest(plain.port, get('/favicon.svg', 'Range: bytes=0-0').replace('GET', 'HEAD'));
  assert.equal(head.status, 206);
  assert.equal(head.headers['content-range'], `bytes 0-0/${favicon.length}`);
  assert.equal(head.body.length, 0);
  // A gzip log is cut as the gzip file it is: its first two bytes are the magic.
  const gz = await rawRequest(plain.port, get('/datasets/intel-corrected.log.gz', 'Range: bytes=0-1'));
  assert.equal(gz.status, 206);
  assert.equal(gz.headers['content-encoding'], undefined);
  assert.deepEqual([...gz.body], [0x1f, 0x8b]);
});

test('a Range header sirv would misread (suffix, several ranges, other units) is ignored: the whole file', async () => {
  for (const range of ['bytes=-5', 'bytes=0-1,5-6', 'items=0-5', 'bytes=x-y', 'bytes=--', 'bytes=1-2-3']) {
    const r = await rawRequest(plain.port, get('/widgets/lib/state.js', `Range: ${range}`));
    assertAlive(plain);
    assert.equal(r.status, 200, `${range} → ${r.status}`);
    assert.deepEqual(r.body, STATE_JS, range);
  }
});

test('a garbage request line and a huge URL are refused and the server stays up', async () => {
  for (const raw of ['HELLO\r\n\r\n', '\x00\x01\x02\r\n\r\n', 'GET\r\n\r\n', 'GET / HTTP/9.9\r\n\r\n', get(`/${'a'.repeat(200_000)}`)]) {
    const r = await rawRequest(plain.port, raw);
    assertAlive(plain);
    assert.ok(r.status === null || (r.status >= 400 && r.status < 500), `${JSON.stringify(raw.slice(0, 20))} → ${r.status}`);
  }
  assert.equal((await rawRequest(plain.port, get('/'))).status, 200);
});

test('other methods than GET and HEAD get 405', async () => {
  const r = await rawRequest(plain.port, 'POST /widgets/lib/state.js HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nConnection: close\r\n\r\n');
  assert.equal(r.status, 405);
  assert.equal(r.headers.allow, 'GET, HEAD');
  const head = await rawRequest(plain.port, `HEAD /widgets/lib/state.js HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`);
  assert.equal(head.status, 200);
});

test('path traversal, plain or percent-encoded, reaches nothing outside the mounts', async () => {
  const pkgJson = fs.readFileSync(path.join(root, 'package.json'));
  for (const target of [
    '/widgets/../package.json', '/widgets/%2e%2e/package.json', '/widgets/%2E%2E/package.json',
    '/widgets/.%2e/package.json', '/widgets/..%2fpackage.json', '/widgets/%2e%2e%2fpackage.json',
    '/pkg/%252e%252e/package.json', '/../package.json', '/%2e%2e/package.json', '/widgets/..\\package.json',
  ]) {
    const r = await rawRequest(plain.port, get(target));
    assertAlive(plain);
    assert.ok(r.status === 400 || r.status === 404, `${target} → ${r.status}`);
    assert.notDeepEqual(r.body, pkgJson, target);
  }
});

test('no dotfile is served, at any depth or encoded', async () => {
  assert.ok(fs.existsSync(path.join(root, 'pkg/.gitignore')), 'pkg/ is built (bash scripts/build.sh)');
  for (const target of ['/pkg/.gitignore', '/pkg/%2egitignore', '/pkg/%2Egitignore', '/pkg/./.gitignore', '/.git/HEAD', '/widgets/.x/state.js']) {
    const r = await rawRequest(plain.port, get(target));
    assertAlive(plain);
    assert.equal(r.status, 404, `${target} → ${r.status}`);
  }
});

test('the test pages are served only by a server asked for them', async () => {
  const r = await rawRequest(plain.port, get('/test-fixtures/real-log.html'));
  assert.equal(r.status, 404);
  const t = await rawRequest(withFixtures.port, get('/test-fixtures/real-log.html'));
  assert.equal(t.status, 200);
});

test('a served name that cannot be read (a socket) fails that request only', async () => {
  const sock = path.join(root, 'tests/browser/fixtures', `unreadable-${process.pid}.sock`);
  const listener = net.createServer();
  await new Promise((resolve) => listener.listen(sock, resolve));
  try {
    const r = await rawRequest(withFixtures.port, get(`/test-fixtures/${path.basename(sock)}`));
    assertAlive(withFixtures);
    assert.ok(r.status === null || r.status >= 400, `→ ${r.status}`);
    assert.equal((await rawRequest(withFixtures.port, get('/test-fixtures/real-log.html'))).status, 200);
  } finally {
    await new Promise((resolve) => listener.close(resolve));
    fs.rmSync(sock, { force: true });
  }
});

test('every response says nosniff', async () => {
  for (const [target, status] of [['/', 200], ['/widgets/lib/state.js', 200], ['/nothing-here', 404], ['//x:1/', 400]]) {
    const r = await rawRequest(plain.port, get(target));
    assert.equal(r.status, status, target);
    assert.equal(r.headers['x-content-type-options'], 'nosniff', target);
  }
});

test('after 1,000 malformed requests the server still answers a normal GET', async () => {
  const bad = [
    get('//x:99999/'), get('/widgets/lib/state.js', 'Range: bytes=100-50'), get('/widgets/lib/state.js', 'Range: bytes=0-99999999999999999999'),
    'HELLO\r\n\r\n', get('/widgets/%zz'), get('/pkg/.gitignore'), get('/widgets/%2e%2e/package.json'), get(`/${'b'.repeat(20_000)}`),
  ];
  const statuses = new Map();
  for (let i = 0; i < 1000; i++) {
    const r = await rawRequest(plain.port, bad[i % bad.length]);
    statuses.set(r.status, (statuses.get(r.status) || 0) + 1);
    if (plain.child.exitCode !== null) break;
  }
  assertAlive(plain);
  assert.ok(!statuses.has(500), `no request reached the last-resort 500: ${[...statuses]}`);
  const ok = await rawRequest(plain.port, get('/widgets/lib/state.js'));
  assert.equal(ok.status, 200);
  assert.deepEqual(ok.body, STATE_JS);
});

// The browser tier's harness when Chromium will not start: the file's tests
// fail with the browser's error, the harness tries the launch again before
// giving up, and the test file's process ends instead of being held open by
// its server (a process that never ends stalls the whole test run).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const HARNESS = pathToFileURL(path.join(root, 'tests/browser/harness.mjs')).href;

test('a browser that cannot start fails the page with its error, after three tries, and lets the process end', async () => {
  const code = `const h = await import(${JSON.stringify(HARNESS)});
try { await h.openPage('/'); console.log('OPENED'); } catch (e) { console.log('REFUSED ' + String(e.message).split('\\n')[0]); }
await h.shutdown();`;
  // /bin/false exits at once: a browser that dies while starting up.
  const child = spawn(process.execPath, ['--input-type=module', '-e', code], {
    stdio: ['ignore', 'pipe', 'pipe'],
    env: { ...process.env, CHROMIUM: '/bin/false' },
  });
  let out = '';
  let err = '';
  child.stdout.on('data', (d) => { out += d; });
  child.stderr.on('data', (d) => { err += d; });
  const code_ = await new Promise((resolve) => child.on('exit', resolve));
  assert.equal(code_, 0, `the process ended by itself (stderr: ${err})`);
  assert.match(out, /^REFUSED /m, 'openPage rejected');
  assert.doesNotMatch(out, /OPENED/);
  assert.equal((err.match(/Chromium did not start \(attempt \d of 3\)/g) ?? []).length, 2, 'two retries reported before the error');
});

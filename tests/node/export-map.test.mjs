// The command-line export (scripts/export-map.mjs) as a user runs it: bad
// option values are named with the text given, a log cut short is mapped
// with a warning naming the line. Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';

const script = new URL('../../scripts/export-map.mjs', import.meta.url).pathname;
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'export-map-'));

function run(...args) {
  const r = spawnSync(process.execPath, [script, ...args], { encoding: 'utf8', timeout: 60_000 });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

/** A small log: `n` FLASER lines of 180 beams 2 m away, robot moving east. */
function smallLog(n) {
  let text = '';
  for (let k = 0; k < n; k++) {
    text += `FLASER 180 ${Array(180).fill('2.00').join(' ')} ${(k * 0.1).toFixed(2)} 0 0 0 0 0 ${k} host ${k}\n`;
  }
  return text;
}

test('a resolution that is not a number is named with the text given', () => {
  const log = path.join(dir, 'small.log');
  fs.writeFileSync(log, smallLog(3));
  for (const text of ['abc', '', '0x10', '1,5']) {
    const r = run(log, path.join(dir, 'out'), '--resolution', text);
    assert.equal(r.status, 1);
    assert.match(r.stderr, new RegExp(`--resolution ${JSON.stringify(text).replace(/[.*+?^${}()|[\]\\]/g, '\\$&')} is not a number`), r.stderr);
    assert.doesNotMatch(r.stderr, /NaN/);
  }
  const eq = run(log, path.join(dir, 'out'), '--resolution=abc');
  assert.match(eq.stderr, /--resolution "abc" is not a number/);
  const ok = run(log, path.join(dir, 'out'), '--resolution', '0.1');
  assert.equal(ok.status, 0, ok.stderr);
});

test('a resolution past what a number holds is named with the text given, not as 0 or Infinity', () => {
  const log = path.join(dir, 'small.log');
  fs.writeFileSync(log, smallLog(3));
  for (const [text, why] of [['1e-400', 'too small'], ['1e999', 'too large'], ['-1e400', 'too large']]) {
    const r = run(log, path.join(dir, 'out'), `--resolution=${text}`);
    assert.equal(r.status, 1);
    assert.match(r.stderr, new RegExp(`--resolution ${text} is ${why}`), r.stderr);
    assert.doesNotMatch(r.stderr, /: 0\b|Infinity/);
  }
});

test('a log cut mid-line is mapped from the complete scans, with a warning naming the line', () => {
  const text = smallLog(10);
  const cut = text.slice(0, text.length - 700);
  const log = path.join(dir, 'cut.log.gz');
  fs.writeFileSync(log, zlib.gzipSync(cut));
  const r = run(log, path.join(dir, 'cut'));
  assert.equal(r.status, 0, r.stderr);
  assert.match(r.stderr, /warning: line 10: the file ends inside this line/);
  const summary = JSON.parse(r.stdout);
  assert.equal(summary.scans, 9);
  assert.match(summary.warning, /the 9 complete scans before it are kept/);
});

test('random bytes are refused in words', () => {
  const bytes = Buffer.alloc(5000);
  let x = 12345;
  for (let i = 0; i < bytes.length; i++) bytes[i] = (x = (x * 1103515245 + 12345) >>> 0) >>> 24;
  const log = path.join(dir, 'noise.bin');
  fs.writeFileSync(log, bytes);
  const r = run(log, path.join(dir, 'noise'));
  assert.equal(r.status, 1);
  assert.match(r.stderr, /neither gzip nor a text log/);
  assert.match(r.stderr, /^[\x20-\x7e\n…]*$/, 'no binary in the message');
});

test('--poses dead-reckoning maps the ACES log at seeded dead-reckoned poses', () => {
  const datasets = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
  const log = path.join(datasets, 'aces-corrected.log.gz');
  const pgm = (prefix) => fs.readFileSync(`${prefix}.pgm`);
  const corrected = run(log, path.join(dir, 'aces'));
  assert.equal(corrected.status, 0, corrected.stderr);
  assert.equal(JSON.parse(corrected.stdout).poses, 'corrected');
  const a = run(log, path.join(dir, 'aces-dr7'), '--poses', 'dead-reckoning', '--seed', '7');
  const again = run(log, path.join(dir, 'aces-dr7b'), '--poses=dead-reckoning', '--seed=7');
  const other = run(log, path.join(dir, 'aces-dr8'), '--poses', 'dead-reckoning', '--seed', '8');
  for (const r of [a, again, other]) assert.equal(r.status, 0, r.stderr);
  const summary = JSON.parse(a.stdout);
  assert.equal(summary.poses, 'dead-reckoning');
  assert.equal(summary.seed, 7);
  assert.ok(pgm(path.join(dir, 'aces-dr7')).equals(pgm(path.join(dir, 'aces-dr7b'))), 'one seed, one map');
  assert.ok(!pgm(path.join(dir, 'aces-dr7')).equals(pgm(path.join(dir, 'aces-dr8'))), 'another seed, another map');
  assert.ok(!pgm(path.join(dir, 'aces-dr7')).equals(pgm(path.join(dir, 'aces'))), 'dead reckoning is not the corrected map');

  for (const text of ['-1', '1.5', 'abc', '1e3']) {
    const r = run(log, path.join(dir, 'bad'), '--poses', 'dead-reckoning', '--seed', text);
    assert.equal(r.status, 1);
    assert.match(r.stderr, /--seed .* is not a whole number/, r.stderr);
  }
  const big = run(log, path.join(dir, 'bad'), '--seed', '9007199254740993');
  assert.match(big.stderr, /--seed 9007199254740993 is too large/);
  const poses = run(log, path.join(dir, 'bad'), '--poses', 'gps');
  assert.equal(poses.status, 1);
  assert.match(poses.stderr, /poses.*gps/, poses.stderr);
  // A source of another kind of log: a corrected log has no odometry of its own.
  const own = run(log, path.join(dir, 'bad'), '--poses', 'odometry');
  assert.equal(own.status, 1);
  assert.match(own.stderr, /the pose source odometry does not apply: the log carries no odometry of its own/, own.stderr);
});

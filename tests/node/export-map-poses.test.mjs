// The command-line export's poses (scripts/export-map.mjs): OUT_PREFIX.poses.tsv
// beside the PGM and YAML for every pose source, one line per scan, the
// poses the map was built with; `--poses scan-matched` the same for one
// seed, bit for bit. Needs pkg/ (npm run build) and the datasets folder.
import test from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';

const script = new URL('../../scripts/export-map.mjs', import.meta.url).pathname;
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'export-map-poses-'));
const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');

function run(...args) {
  const r = spawnSync(process.execPath, [script, ...args], { encoding: 'utf8', timeout: 120_000 });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

/** The laser poses of a log's FLASER lines, as written (x, y, theta after the ranges). */
function logPoses(file) {
  const text = zlib.gunzipSync(fs.readFileSync(file)).toString('latin1');
  return text.split('\n').filter((l) => l.startsWith('FLASER')).map((l) => {
    const t = l.trim().split(/\s+/);
    const n = Number(t[1]);
    return t.slice(2 + n, 5 + n).map(Number);
  });
}

/** `scan x y theta` lines as numbers, checking the scan column counts up from 0. */
function readTsv(file) {
  return fs.readFileSync(file, 'utf8').trim().split('\n').map((line, k) => {
    const t = line.split(' ');
    assert.equal(t.length, 4, line);
    assert.equal(t[0], String(k));
    return t.slice(1).map(Number);
  });
}

const log = path.join(DATASETS, 'aces-corrected.log.gz');

test('poses.tsv holds the poses each source mapped with, one line per scan', { skip: !fs.existsSync(log) && 'no datasets folder' }, () => {
  const truth = logPoses(log);
  const corrected = run(log, path.join(dir, 'c'));
  assert.equal(corrected.status, 0, corrected.stderr);
  assert.equal(JSON.parse(corrected.stdout).poses_tsv, path.join(dir, 'c.poses.tsv'));
  const c = readTsv(path.join(dir, 'c.poses.tsv'));
  assert.equal(c.length, truth.length);
  // The corrected poses are the log's (kept as f64 from the text).
  for (const [k, p] of c.entries()) for (let i = 0; i < 3; i++) assert.ok(Math.abs(p[i] - truth[k][i]) < 1e-9, `scan ${k}`);

  const dr = run(log, path.join(dir, 'dr'), '--poses', 'dead-reckoning', '--seed', '2');
  assert.equal(dr.status, 0, dr.stderr);
  const d = readTsv(path.join(dir, 'dr.poses.tsv'));
  assert.equal(d.length, truth.length);
  assert.deepEqual(d[0], c[0], 'dead reckoning starts where the log does');
  assert.ok(Math.hypot(d.at(-1)[0] - c.at(-1)[0], d.at(-1)[1] - c.at(-1)[1]) > 1, 'and wanders off');

  const a = run(log, path.join(dir, 'sm'), '--poses', 'scan-matched', '--seed', '2');
  const b = run(log, path.join(dir, 'sm2'), '--poses=scan-matched', '--seed=2');
  assert.equal(a.status, 0, a.stderr);
  assert.equal(b.status, 0, b.stderr);
  const summary = JSON.parse(a.stdout);
  assert.deepEqual([summary.poses, summary.seed, summary.scans], ['scan-matched', 2, truth.length]);
  const s = readTsv(path.join(dir, 'sm.poses.tsv'));
  assert.equal(s.length, truth.length);
  // One seed, one path and one map, bit for bit.
  assert.equal(fs.readFileSync(path.join(dir, 'sm.poses.tsv'), 'utf8'), fs.readFileSync(path.join(dir, 'sm2.poses.tsv'), 'utf8'));
  assert.ok(fs.readFileSync(path.join(dir, 'sm.pgm')).equals(fs.readFileSync(path.join(dir, 'sm2.pgm'))));
  assert.match(fs.readFileSync(path.join(dir, 'sm.yaml'), 'utf8'), /\n# poses: scan-matched \(seed 2\)/);
  // Matched from the same dead reckoning, it stays far nearer the log's poses.
  const err = (ps) => Math.max(...ps.map((p, k) => Math.hypot(p[0] - truth[k][0], p[1] - truth[k][1])));
  assert.ok(err(s) < err(d) / 5, `matched ${err(s).toFixed(2)} m, dead reckoning ${err(d).toFixed(2)} m`);
});

test('an unknown pose source is refused by name, and nothing is written', () => {
  const small = path.join(dir, 'small.log');
  fs.writeFileSync(small, 'FLASER 3 1.0 1.0 1.0 0 0 0 0 0 0 0 h 0\n');
  const r = run(small, path.join(dir, 'bad'), '--poses', 'scan-match');
  assert.equal(r.status, 1);
  assert.match(r.stderr, /poses.*scan-match/, r.stderr);
  assert.equal(fs.existsSync(path.join(dir, 'bad.poses.tsv')), false);
});

// The command-line export of a ROS 2 bag (scripts/export-map.mjs BAG.mcap):
// the shared Intel bag whose odometry is the corrected path maps like the
// corrected Intel log (the same counts within 1 %), at the pose sources
// that apply to a bag; the others are refused by name, and a topic the bag
// lacks is refused with the bag's topics. Needs pkg/ (npm run build) and
// ../shared/datasets (skipped without it).
import test from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const script = new URL('../../scripts/export-map.mjs', import.meta.url).pathname;
const DATASETS = process.env.OCCGRID_DATASETS || new URL('../../../shared/datasets', import.meta.url).pathname;
const bag = path.join(DATASETS, 'intel-perfect.mcap');
const log = path.join(DATASETS, 'intel-corrected.log.gz');
const skip = !fs.existsSync(bag) || !fs.existsSync(log) ? 'no shared datasets' : false;
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'export-map-bag-'));

function run(...args) {
  const r = spawnSync(process.execPath, [script, ...args], { encoding: 'utf8', timeout: 300_000 });
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

let atOdometry = null; // the first test's export at --poses odometry

test('intel-perfect.mcap at its odometry maps like the corrected Intel log', { skip }, () => {
  const fromBag = run(bag, path.join(dir, 'bag'), '--poses', 'odometry', '--scan-topic', '/scan', '--odom-topic=/odom');
  assert.equal(fromBag.status, 0, fromBag.stderr);
  const fromLog = run(log, path.join(dir, 'log'));
  assert.equal(fromLog.status, 0, fromLog.stderr);
  const a = JSON.parse(fromBag.stdout);
  const b = JSON.parse(fromLog.stdout);
  atOdometry = a;
  // Without --poses, the CARMEN log is mapped at its own corrected poses.
  assert.equal(b.poses, 'corrected');
  assert.equal(a.poses, 'odometry');
  assert.equal(a.scans, b.scans);
  for (const key of ['occupied', 'free', 'unknown']) {
    assert.ok(Math.abs(a[key] - b[key]) <= 0.01 * b[key], `${key}: ${a[key]} from the bag, ${b[key]} from the log`);
  }
  // One line per scan: the laser's pose in the odometry frame, the log's.
  const rows = (file) => fs.readFileSync(file, 'utf8').trim().split('\n').map((l) => l.trim().split(/\s+/).map(Number));
  const pa = rows(a.poses_tsv);
  const pb = rows(b.poses_tsv);
  assert.equal(pa.length, pb.length);
  for (let k = 0; k < pa.length; k++) assert.ok(Math.hypot(pa[k][1] - pb[k][1], pa[k][2] - pb[k][2]) < 1e-3, `scan ${k}`);
});

test('a bag refuses corrected and dead-reckoning poses by name, and a topic it lacks with its topics', { skip }, () => {
  for (const poses of ['corrected', 'dead-reckoning']) {
    const r = run(bag, path.join(dir, 'no'), '--poses', poses);
    assert.equal(r.status, 1);
    assert.match(r.stderr, new RegExp(`the pose source ${poses} does not apply`), r.stderr);
  }
  const r = run(bag, path.join(dir, 'no'), '--poses', 'odometry', '--scan-topic', '/front_scan');
  assert.equal(r.status, 1);
  assert.match(r.stderr, /scan_topic "\/front_scan" is no sensor_msgs\/msg\/LaserScan topic/, r.stderr);
  assert.match(r.stderr, /"\/odom" \("nav_msgs\/msg\/Odometry", \d+ messages\)/, r.stderr);
});

test('a bag without --poses is mapped at its own odometry, the map --poses odometry makes', { skip }, () => {
  const r = run(bag, path.join(dir, 'default'));
  assert.equal(r.status, 0, r.stderr);
  const a = JSON.parse(r.stdout);
  assert.equal(a.poses, 'odometry');
  const b = atOdometry ?? JSON.parse(run(bag, path.join(dir, 'odometry'), '--poses', 'odometry').stdout);
  assert.deepEqual(fs.readFileSync(a.pgm), fs.readFileSync(b.pgm));
  assert.equal(fs.readFileSync(a.poses_tsv, 'utf8'), fs.readFileSync(b.poses_tsv, 'utf8'));
});

// Map Weaver's real-log panel in Chromium with ROS 2 bags it writes itself
// (MCAP records, CDR messages, no compression): a bag of two LaserScan
// topics is refused until the reader chooses one, the chooser lists each
// topic with its type and message count, and the bag maps once a topic is
// picked; a bag opened at the panel's defaults is mapped at its own
// odometry (a bag without a map → odom transform has no corrected poses),
// and a CARMEN log opened after it at its corrected poses again; a bag with
// map → odom on /tf is mapped at its corrected poses once read, and a bag
// without one after it at its odometry again.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const PAGE = '/test-fixtures/real-log.html';
const MAGIC = [0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a];

/** Little-endian bytes, appended with alignment as CDR wants (relative to the 4-byte encapsulation header). */
class Bytes {
  constructor(cdr = false) {
    this.b = cdr ? [0, 1, 0, 0] : [];
    this.base = cdr ? 4 : 0;
  }
  align(n) { while ((this.b.length - this.base) % n) this.b.push(0); return this; }
  num(kind, n, v) {
    if (this.base) this.align(n);
    const d = new DataView(new ArrayBuffer(n));
    d[kind](0, v, true);
    this.b.push(...new Uint8Array(d.buffer));
    return this;
  }
  u16(v) { return this.num('setUint16', 2, v); }
  u32(v) { return this.num('setUint32', 4, v); }
  i32(v) { return this.num('setInt32', 4, v); }
  u64(v) { return this.num('setBigUint64', 8, BigInt(v)); }
  f32(v) { return this.num('setFloat32', 4, v); }
  f64(v) { return this.num('setFloat64', 8, v); }
  /** An MCAP string (u32 length, no terminator). */
  str(s) { const e = new TextEncoder().encode(s); this.u32(e.length); this.b.push(...e); return this; }
  /** A CDR string (u32 length with the terminating NUL). */
  cdrStr(s) { const e = new TextEncoder().encode(s); this.u32(e.length + 1); this.b.push(...e, 0); return this; }
  raw(bytes) { this.b.push(...bytes); return this; }
}

const HEADER_DEF = `================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
`;
const SCAN_DEF = `std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\nfloat32[] intensities\n${HEADER_DEF}`;
const ODOM_DEF = `std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n${HEADER_DEF}================================================================================
MSG: geometry_msgs/PoseWithCovariance
Pose pose
float64[36] covariance
================================================================================
MSG: geometry_msgs/Pose
Point position
Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x 0
float64 y 0
float64 z 0
float64 w 1
`;
const TF_DEF = `geometry_msgs/TransformStamped[] transforms\n================================================================================
MSG: geometry_msgs/TransformStamped
std_msgs/Header header
string child_frame_id
Transform transform
================================================================================
MSG: geometry_msgs/Transform
Vector3 translation
Quaternion rotation
${HEADER_DEF}`;

function header(c, t, frame) {
  const sec = Math.floor(t);
  return c.i32(sec).u32(Math.round((t - sec) * 1e9)).cdrStr(frame);
}
function planar(c, [x, y, th]) {
  return c.f64(x).f64(y).f64(0).f64(0).f64(0).f64(Math.sin(th / 2)).f64(Math.cos(th / 2));
}

/**
 * A bag of a robot driving a straight line in a square room: `scanTopics`
 * LaserScan topics (the same scans on each), one `/odom`, the laser on
 * `/tf_static`, and with `mapOdom` a `map → odom` transform on `/tf`
 * before each scan; records unchunked, no summary (the reader does not
 * need one).
 */
function robotBag(scanTopics, scans = 8, mapOdom = false) {
  const out = new Bytes().raw(MAGIC);
  const record = (op, body) => out.raw([op]).u64(body.b.length).raw(body.b);
  record(0x01, new Bytes().str('ros2').str('occgrid browser tests'));
  const schemas = [['sensor_msgs/msg/LaserScan', SCAN_DEF], ['nav_msgs/msg/Odometry', ODOM_DEF], ['tf2_msgs/msg/TFMessage', TF_DEF]];
  schemas.forEach(([name, def], i) => record(0x03, new Bytes().u16(i + 1).str(name).str('ros2msg').str(def)));
  const channel = (id, schema, topic) => record(0x04, new Bytes().u16(id).u16(schema).str(topic).str('cdr').u32(0));
  scanTopics.forEach((t, i) => channel(i + 1, 1, t));
  const odomId = scanTopics.length + 1;
  const tfId = odomId + 1;
  channel(odomId, 2, '/odom');
  channel(tfId, 3, '/tf_static');
  const tfMovingId = tfId + 1;
  if (mapOdom) channel(tfMovingId, 3, '/tf');
  const message = (id, t, c) => record(0x05, new Bytes().u16(id).u32(0).u64(Math.round(t * 1e9)).u64(Math.round(t * 1e9)).raw(c.b));
  const t0 = 1_700_000_000;
  const tf = new Bytes(true).u32(1);
  planar(header(tf, t0, 'base_link').cdrStr('laser'), [0.2, 0, 0]);
  message(tfId, t0, tf);
  const base = (t) => [0.3 * (t - t0), 0, 0];
  const odom = (t) => {
    const c = header(new Bytes(true), t, 'odom').cdrStr('base_link');
    planar(c, base(t));
    for (let i = 0; i < 36 + 6 + 36; i++) c.f64(0);
    message(odomId, t, c);
  };
  const beams = 181;
  const step = Math.PI / (beams - 1);
  odom(t0 - 0.1);
  for (let k = 0; k < scans; k++) {
    const t = t0 + 0.5 * k;
    if (mapOdom) {
      const m = new Bytes(true).u32(1);
      planar(header(m, t, 'map').cdrStr('odom'), [1.5, -0.5, 0.1]);
      message(tfMovingId, t, m);
    }
    const [x] = base(t);
    // A 10 m square room around the path, centred on the origin.
    const ranges = [];
    for (let i = 0; i < beams; i++) {
      const a = -Math.PI / 2 + i * step;
      const [dx, dy] = [Math.cos(a), Math.sin(a)];
      const toX = dx > 0 ? (5 - x - 0.2) / dx : dx < 0 ? (-5 - x - 0.2) / dx : Infinity;
      const toY = dy !== 0 ? 5 / Math.abs(dy) : Infinity;
      ranges.push(Math.min(toX, toY));
    }
    for (let s = 1; s <= scanTopics.length; s++) {
      const c = header(new Bytes(true), t, 'laser').f32(-Math.PI / 2).f32(Math.PI / 2).f32(step).f32(0).f32(0.1).f32(0.05).f32(20).u32(beams);
      for (const r of ranges) c.f32(r);
      c.u32(0);
      message(s, t, c);
    }
    odom(t + 0.0002);
    odom(t + 0.25);
  }
  record(0x0f, new Bytes().u32(0));
  record(0x02, new Bytes().u64(0).u64(0).u32(0));
  out.raw(MAGIC);
  return Buffer.from(out.b);
}

/** Waits until the session's state is `state` and the panel shows it (or it failed), then returns the state. */
async function settled(page, wanted) {
  await page.waitForFunction((w) => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    return !!s && s.state === panel.root.dataset.state && (s.state === w || s.state === 'failed');
  }, wanted, { timeout: 60_000 });
  return page.evaluate(() => window.realLogPanel.session.state());
}

async function openPanel() {
  const opened = await openPage(PAGE);
  await opened.page.waitForSelector('#panel[data-ready]');
  return opened;
}

test('a bag of two LaserScan topics offers them (topic, type, messages) and maps the one chosen', async () => {
  const { page, errors, close } = await openPanel();
  const chooser = page.locator('.map-weaver-log-topics');
  assert.equal(await chooser.isHidden(), true, 'no choice before a bag wants one');
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'two-scans.mcap', mimeType: 'application/octet-stream', buffer: robotBag(['/front_scan', '/rear_scan']) });
  const refused = await settled(page, 'done');
  assert.equal(refused.state, 'failed');
  assert.deepEqual(refused.topics.scanTopics.map((t) => [t.topic, t.type, t.messages]),
    [['/front_scan', 'sensor_msgs/msg/LaserScan', 8], ['/rear_scan', 'sensor_msgs/msg/LaserScan', 8]]);
  await chooser.waitFor({ state: 'visible' });
  const scanOptions = await page.locator('.map-weaver-log-topics select[name=scan-topic] option').allTextContents();
  assert.deepEqual(scanOptions, ['/front_scan (sensor_msgs/msg/LaserScan, 8 messages)', '/rear_scan (sensor_msgs/msg/LaserScan, 8 messages)']);
  const odomOptions = await page.locator('.map-weaver-log-topics select[name=odom-topic] option').allTextContents();
  assert.equal(odomOptions.length, 1);
  assert.match(odomOptions[0], /^\/odom \(nav_msgs\/msg\/Odometry, \d+ messages\)$/);

  await page.selectOption('.map-weaver-log-topics select[name=scan-topic]', '/rear_scan');
  await page.click('.map-weaver-log-topics button[name=map-topics]');
  const mapped = await settled(page, 'done');
  assert.equal(mapped.state, 'done', mapped.error);
  assert.equal(mapped.topics, null);
  assert.equal(mapped.scansDone, 8);
  // A bag at the panel's defaults: its own odometry, as the poses menu says.
  assert.equal(mapped.panes[0].poses, 'odometry');
  assert.equal(await page.inputValue('.map-weaver-log select[name=poses]'), 'odometry');
  assert.equal(await chooser.isHidden(), true, 'the chooser goes once the topics are chosen');
  assert.equal(await page.locator('.map-weaver-log [role=alert]').count(), 0, 'the refusal goes too');
  // The one error of the page: the core's refusal, naming the bag's topics.
  assert.equal(errors.length, 1, errors.join('\n'));
  assert.match(errors[0], /the bag has 2 sensor_msgs\/msg\/LaserScan topics/);
  await close();
});

test('a bag at the defaults maps at its odometry; a CARMEN log after it at its corrected poses', async () => {
  const { page, errors, close } = await openPanel();
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'one-scan.mcap', mimeType: 'application/octet-stream', buffer: robotBag(['/scan']) });
  const bag = await settled(page, 'done');
  assert.equal(bag.state, 'done', bag.error);
  assert.equal(bag.panes[0].poses, 'odometry');
  assert.equal(await page.locator('.map-weaver-log-topics').isHidden(), true, 'one topic of each: no choice');
  // A CARMEN log of three scans, written here: corrected poses again.
  const line = (k) => `FLASER 5 2.0 2.0 2.0 2.0 2.0 ${k * 0.1} 0 0 ${k * 0.1} 0 0 ${k} host ${k}`;
  const carmen = Buffer.from([0, 1, 2].map(line).join('\n') + '\n');
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'three.log', mimeType: 'text/plain', buffer: carmen });
  await page.waitForFunction(() => window.realLogPanel.session.state().log === 'three.log');
  const log = await settled(page, 'done');
  assert.equal(log.state, 'done', log.error);
  assert.equal(log.panes[0].poses, 'corrected');
  assert.deepEqual(errors, []);
  await close();
});

test('a bag with map → odom maps at its corrected poses once read; a bag without one after it at its odometry', async () => {
  const { page, errors, close } = await openPanel();
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'localised.mcap', mimeType: 'application/octet-stream', buffer: robotBag(['/scan'], 8, true) });
  await page.waitForFunction(() => window.realLogPanel.session?.state().panes[0]?.poses === 'corrected', null, { timeout: 60_000 });
  const localised = await settled(page, 'done');
  assert.equal(localised.state, 'done', localised.error);
  assert.equal(localised.panes[0].poses, 'corrected');
  assert.equal(localised.scansDone, 8);
  assert.equal(await page.inputValue('.map-weaver-log select[name=poses]'), 'corrected');
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'plain.mcap', mimeType: 'application/octet-stream', buffer: robotBag(['/scan']) });
  await page.waitForFunction(() => window.realLogPanel.session.state().log === 'plain.mcap');
  const plain = await settled(page, 'done');
  assert.equal(plain.state, 'done', plain.error);
  assert.equal(plain.panes[0].poses, 'odometry');
  assert.equal(await page.inputValue('.map-weaver-log select[name=poses]'), 'odometry');
  assert.deepEqual(errors, []);
  await close();
});

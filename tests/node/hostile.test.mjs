// Hostile JavaScript arguments: objects whose getters throw,
// proxies whose traps throw, and numbers-to-be whose `valueOf` frees the
// very instance being called. None may poison a session: the call is
// refused with an Error naming the parameter (or the page's own free()
// takes effect cleanly), and every other instance keeps answering.
// Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import { loadCore } from '../../scripts/lib/load-core.mjs';
import { refuses } from './refuses.mjs';

const { core } = await loadCore();
/** The real-log module of the core (`RealLogSession`), loaded on its own as the page does. */
const logs = (await loadCore({ logs: true })).core;

const FLASER = new TextEncoder().encode(
  'FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n'.repeat(5));

/**
 * A number-to-be whose `valueOf` (and `toString`) frees `target()`: the
 * glue converting it while the instance is in use would run the call on
 * freed memory. Counts how often JavaScript asked it for a number.
 */
function freeing(target) {
  const h = {
    asked: 0,
    valueOf() {
      h.asked += 1;
      try {
        target().free();
      } catch {
        // Already freed: still a number.
      }
      return 1;
    },
  };
  h.toString = h.valueOf;
  return h;
}

/**
 * For every number parameter of `methods` (`[name, args]`, `HOSTILE`
 * marking the parameter), calls `instance[name]` with a freeing object
 * there: the call must be refused naming `field`, `valueOf` must never
 * run, and `alive(instance)` must still answer.
 */
const HOSTILE = Symbol('hostile');
function survives(instance, methods, alive) {
  for (const [name, args, field] of methods) {
    const h = freeing(() => instance);
    const call = args.map((a) => (a === HOSTILE ? h : a));
    refuses(() => instance[name](...call), `invalid ${field}`, 'expected a number');
    assert.equal(h.asked, 0, `${name}: the glue asked the object for a number`);
    assert.ok(instance.__wbg_ptr !== 0, `${name}: the instance was freed`);
    alive(instance, name);
  }
}

test('Map Weaver: a valueOf that frees the run is never called; the run keeps mapping', () => {
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  assert.equal(w.advance(2), 2);
  survives(w, [
    ['advance', [HOSTILE], 'scans'],
    ['checkFastForward', [HOSTILE], 'scans'],
    ['pixels', [HOSTILE], 'pane'],
    ['entropyCurve', [HOSTILE], 'pane'],
    ['brierCurve', [HOSTILE], 'pane'],
    ['trackedHistory', [HOSTILE], 'pane'],
    ['cellInfo', [HOSTILE, 0, 0], 'pane'],
    ['cellInfo', [0, HOSTILE, 0], 'col'],
    ['cellInfo', [0, 0, HOSTILE], 'row'],
    ['overlay', [HOSTILE], 'pane'],
    ['stagePane', [HOSTILE, { clamp: 3 }], 'pane'],
    ['paneSize', [HOSTILE], 'pane'],
    ['recordFrameMs', [HOSTILE], 'ms'],
    ['exportMap', [HOSTILE], 'pane'],
  ], (x, name) => assert.equal(x.advance(1), 1, `advances after ${name}`));
  // Numeric strings are no numbers either: the glue used to coerce them.
  refuses(() => w.advance('3'), 'invalid scans: "3" (expected a number)');
  refuses(() => w.stagePane(0, { clamp: '4' }), 'invalid panes[0].clamp', '"4"');
  // Inside a patch the freeing object is read as the plain data it holds
  // (its methods are refused by name), never converted to a number.
  for (const field of ['clamp', 'strength', 'betaDeg', 'beams', 'resolution']) {
    const h = freeing(() => w);
    refuses(() => w.stagePane(1, { [field]: h }), `invalid panes[1].${field}`);
    assert.equal(h.asked, 0, `stagePane ${field}: asked the object for a number`);
  }
  assert.ok(w.readout().scans > 2);
  w.free();
});

test('setPerson takes true or false, never a value it would have to convert', () => {
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  assert.equal(w.advance(2), 2);
  // A true-or-false parameter took the glue's coercion, which ran valueOf
  // after taking the run's pointer: the run was freed mid-call and the
  // allocator's assertion stopped the core (`unreachable`).
  const toPrimitive = { asked: 0, [Symbol.toPrimitive]() { toPrimitive.asked += 1; w.free(); return true; } };
  for (const hostile of [freeing(() => w), toPrimitive]) {
    refuses(() => w.setPerson(hostile), 'invalid person', 'expected true or false');
    assert.equal(hostile.asked, 0, 'the glue asked the object for a value');
    assert.ok(w.__wbg_ptr !== 0, 'setPerson: the run was freed');
    assert.equal(w.advance(1), 1, 'advances after setPerson');
  }
  w.setPerson(false);
  assert.equal(w.readout().person, false);
  w.free();
  // The core is whole: another run builds and maps.
  const fresh = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  assert.equal(fresh.advance(2), 2);
  fresh.free();
});

/** A Proxy that has been revoked: every question put to it throws a TypeError. */
function revoked() {
  const { proxy, revoke } = Proxy.revocable({}, {});
  revoke();
  return proxy;
}

test('a revoked Proxy is an invalid settings object: the instance and the core stay usable', () => {
  const s = new logs.RealLogSession(FLASER);
  assert.equal(s.read(2).scans, 2);
  // `Array.isArray` on it threw through the core while the session was
  // borrowed: every later call said "recursive use of an object", and
  // free() "attempted to take ownership of Rust value while it was borrowed".
  for (const bad of [revoked(), { resolution: revoked() }, { clamp: [revoked()] }]) {
    refuses(() => s.configure(bad), 'invalid settings', 'revoked');
  }
  refuses(() => s.configure({ resolution: revoked() }), 'invalid settings.resolution');
  assert.equal(s.read(Infinity).scans, 5, 'the session reads on');
  assert.ok(s.configure({ clamp: 3 }).width > 0);
  assert.equal(s.buildSlice(Infinity).scansDone, 5);

  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  refuses(() => w.stagePane(0, revoked()), 'invalid panes[0]', 'revoked');
  refuses(() => w.stagePane(0, { clamp: revoked() }), 'invalid panes[0].clamp', 'revoked');
  refuses(() => new core.MapWeaver(revoked()), 'invalid settings', 'revoked');
  refuses(() => new core.MapWeaver({ scene: revoked() }), 'invalid settings.scene', 'revoked');
  assert.equal(w.advance(1), 1);
  w.stagePane(0, { clamp: 3 });
  assert.equal(w.readout().panes[0].clamp, 3);
  w.free();
  s.free();

  // Each exception that unwound through the core also kept the stack its
  // frames had taken: call 1,559 wrote past the core's stack ("memory
  // access out of bounds"), and the core was dead for good.
  for (let i = 0; i < 3000; i++) refuses(() => core.jointPosterior(revoked()), 'invalid joint query');
  const fresh = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  assert.equal(fresh.advance(2), 2, 'a new run builds and maps');
  fresh.free();
  assert.equal(core.jointAnswer(core.chapterTwoCellQuery()).joint.length, 4);
});

test('a "__proto__" field of a settings or scene object is refused by name, not dropped', () => {
  // JSON.parse makes "__proto__" an own field (a page's attribute text
  // goes through it); copying it by assignment made it the copy's
  // prototype, and the field vanished unread.
  const scene = JSON.parse('{"__proto__": {"scan_rate": 1}}');
  refuses(() => new core.MapWeaver({ laps: 1, scene }), 'invalid settings.scene', 'unknown field "__proto__"');
  refuses(() => new core.MapWeaver(JSON.parse('{"__proto__": {"laps": 1}}')), 'invalid settings', 'unknown field "__proto__"');
  refuses(() => new core.DoorwayTrap(JSON.parse('{"__proto__": {"seed": 3}}')), 'invalid scene', '"__proto__"');
  refuses(() => new core.SensorFusion(JSON.parse('{"lidar": {"__proto__": {"beams": 2}}}'), undefined), 'invalid scene.lidar', '"__proto__"');
  const s = new logs.RealLogSession(FLASER);
  s.read(Infinity);
  refuses(() => s.configure(JSON.parse('{"__proto__": {"clamp": 1}}')), 'invalid settings', '"__proto__"');
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  refuses(() => w.stagePane(0, JSON.parse('{"__proto__": {"clamp": 1}}')), 'invalid panes[0]', '"__proto__"');
  assert.notEqual(w.readout().panes[0].clamp, 1);
  refuses(() => core.jointPosterior(JSON.parse('{"__proto__": {}}')), 'invalid joint query', '"__proto__"');
  // "constructor" is no setting either.
  refuses(() => s.configure({ constructor: 1 }), 'invalid settings', 'unknown field "constructor"');
  w.free();
  s.free();
});

test('bytes are told by their internal slots: a Proxy or a look-alike of a Uint8Array is refused', () => {
  const log = FLASER;
  const lying = new Uint8Array(log);
  Object.defineProperty(lying, 'length', { get() { throw new Error('no length'); } });
  // A real Uint8Array with a lying `length` is read by its real length.
  assert.equal(new logs.RealLogSession(lying).read(Infinity).scans, 5);
  const shrinking = new Uint8Array([1, 0, 1]);
  let asked = 0;
  Object.defineProperty(shrinking, 'length', { get() { asked += 1; return asked === 1 ? 3 : 1; } });
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, shrinking, true).steps.length, 3);
  assert.equal(asked, 0, 'the length getter never ran');
  for (const fake of [new Proxy(new Uint8Array(log), {}), Object.setPrototypeOf({ length: 3 }, Uint8Array.prototype), revoked()]) {
    refuses(() => new logs.RealLogSession(fake), 'invalid bytes', 'Uint8Array');
    refuses(() => core.zipMapPair('m', fake, 'image: m.pgm\n'), 'invalid pgm');
    refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, fake, true), 'invalid readings');
  }
  // A Proxy of an array of readings is read item by item through its traps.
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, new Proxy([1, 0], {}), true).steps.length, 2);
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Proxy([1, 0], { get(t, k) { if (k === '1') throw new Error('trap'); return t[k]; } }), true), 'invalid readings[1]', 'trap');
  // A detached buffer holds no bytes.
  const buffer = new ArrayBuffer(8);
  structuredClone(buffer, { transfer: [buffer] });
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, buffer, true).steps.length, 0);
});

test('RealLogSession: throwing getters and proxies in settings, freeing valueOf in counts', () => {
  const s = new logs.RealLogSession(FLASER);
  assert.equal(s.read(Infinity).finished, true);
  assert.ok(s.configure({}));
  const getter = { get resolution() { throw new Error('boom'); } };
  refuses(() => s.configure(getter), 'invalid settings', 'boom');
  const proxy = new Proxy({}, { ownKeys() { throw new Error('no keys'); } });
  refuses(() => s.configure(proxy), 'invalid settings', 'no keys');
  const trap = new Proxy({}, { get() { throw new Error('no get'); }, ownKeys: () => ['clamp'], getOwnPropertyDescriptor: () => ({ value: 1, enumerable: true, configurable: true }) });
  refuses(() => s.configure(trap), 'invalid settings', 'no get');
  // The session was not left "in use": every later call answers.
  assert.equal(s.configure({ clamp: 3 }).width > 0, true);
  survives(s, [
    ['read', [HOSTILE], 'maxScans'],
    ['buildSlice', [HOSTILE], 'maxCells'],
    ['buildSlice', [1, HOSTILE], 'withinMs'],
    ['seek', [HOSTILE], 'scan'],
    ['cellAt', [HOSTILE, 0, 0], 'pane'],
    ['cellAt', [0, HOSTILE, 0], 'col'],
    ['cellAt', [0, 0, HOSTILE], 'row'],
    ['robotAt', [0, HOSTILE], 'scan'],
  ], (x, name) => assert.equal(typeof x.state().scansDone, 'number', `answers after ${name}`));
  // The pane beside is asked for through the settings, read as configure reads them.
  refuses(() => s.configure({ poses: 'gps' }), 'poses', 'gps');
  refuses(() => s.configure({ seed: 2 ** 53 }), 'seed', '9007199254740992');
  s.configure({ poses: 'dead-reckoning', seed: 3 });
  // A time bound of no time, or of no number, is refused by name; the map is untouched.
  for (const bad of [0, -5, NaN, '20']) refuses(() => s.buildSlice(Infinity, bad), 'withinMs', String(bad));
  assert.equal(s.state().work, 0, 'a refused call built nothing');
  const done = s.buildSlice(Infinity, 1e9);
  assert.equal(done.finished, true);
  assert.equal(done.panes.length, 2);
  assert.equal(done.scansDone, 5, 'the build saw every scan: no garbage counts');
  survives(s, [
    ['setViewSize', [0, HOSTILE, 10], 'width'],
    ['zoomAt', [0, 0, 0, HOSTILE], 'factor'],
    ['panBy', [0, HOSTILE, 0], 'dx'],
    ['cellAtView', [0, 0, HOSTILE], 'y'],
    ['moveCursor', [0, HOSTILE, 0, false], 'dx'],
    ['viewLegend', [1, HOSTILE], 'devicePixelRatio'],
  ], (x, name) => assert.equal(typeof x.view(0).scale, 'number', `answers after ${name}`));
  assert.ok(s.renderView(1) > 0);
  s.free();
});

test('a getter that frees its own session while configure reads it: freed cleanly, nothing else hurt', () => {
  const s = new logs.RealLogSession(FLASER);
  s.read(Infinity);
  const other = new logs.RealLogSession(FLASER);
  other.read(Infinity);
  const settings = { get clamp() { s.free(); return 3; } };
  // The free happens inside the call; the page asked for it, so the
  // session ends, but with Errors, not a trap or a panic.
  try {
    s.configure(settings);
  } catch (e) {
    assert.ok(e instanceof Error && !(e instanceof WebAssembly.RuntimeError), String(e));
  }
  const later = refuses(() => s.state(), '');
  assert.doesNotMatch(later, /unreachable|recursive use/);
  assert.equal(other.buildSlice(Infinity).scansDone, 5, 'another session still maps');
  // Likewise while configure reads the settings that add a pane.
  const freeing = { poses: 'dead-reckoning', get seed() { other.free(); return 3; } };
  try {
    other.configure(freeing);
  } catch (e) {
    assert.ok(e instanceof Error && !(e instanceof WebAssembly.RuntimeError), String(e));
  }
  assert.doesNotMatch(refuses(() => other.state(), ''), /unreachable|recursive use/);
});

test('the doorway trap, the fusion widget, the workbench and the cell filter never coerce a number', () => {
  const t = new core.DoorwayTrap(undefined);
  survives(t, [
    ['mapRun', [HOSTILE], 'maxFlips'],
    ['cellInfo', [HOSTILE, 0], 'ix'],
    ['cellInfo', [0, HOSTILE], 'iy'],
  ], (x) => assert.ok(x.mapStep() !== undefined));
  refuses(() => new core.DoorwayTrap({ get seed() { throw new Error('seedless'); } }), 'invalid scene', 'seedless');
  assert.ok(t.report());
  t.free();

  const f = new core.SensorFusion(undefined, undefined);
  survives(f, [['setLidarBeams', [HOSTILE], 'lidar.beams']], (x) => assert.equal(typeof x.step(), 'boolean'));
  refuses(() => new core.SensorFusion(new Proxy({}, { ownKeys() { throw new Error('trap'); } }), undefined), 'invalid scene', 'trap');
  assert.ok(f.readout().step > 0);
  f.free();

  const freeingSeed = freeing(() => ({ free() {} }));
  refuses(() => new core.InverseWorkbench(freeingSeed), 'invalid seed', 'expected a number');
  assert.equal(freeingSeed.asked, 0);
  const b = new core.InverseWorkbench(undefined);
  const lattice = { minRange: 0.1, maxRange: 4, ranges: 8, maxBearing: 0.2, bearings: 5 };
  survives(b, [
    ['retrain', [HOSTILE], 'seed'],
    ['view', [HOSTILE, lattice], 'z'],
    ['setDensity', [HOSTILE], 'density'],
  ], (x) => assert.ok(x.readout().run));
  refuses(() => b.view(2, { get ranges() { throw new Error('lattice trap'); } }), 'invalid lattice', 'lattice trap');
  assert.ok(b.view(2, lattice).hand.length > 0);
  b.free();

  for (const k of [0, 1]) {
    const h = freeing(() => ({ free() {} }));
    const zs = [2, 2];
    zs[k] = h;
    refuses(() => core.forwardDensity(zs[0], zs[1], undefined), `invalid ${k ? 'z_star' : 'z'}`, 'expected a number');
    assert.equal(h.asked, 0);
  }
  for (const [k, field] of ['p_occ', 'p_free', 'prior', 'clamp'].entries()) {
    const args = [0.7, 0.3, 0.5, 12];
    const h = freeing(() => ({ free() {} }));
    args[k] = h;
    refuses(() => core.runCellFilter(...args, new Uint8Array([1]), true), `invalid ${field}`, 'expected a number');
    assert.equal(h.asked, 0);
  }
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1, 0]), true).steps.length, 2);
});

/** Runs `f`, which must be refused naming every word, and returns how long the refusal took, ms. */
function refusalMs(f, ...words) {
  const started = performance.now();
  refuses(f, ...words);
  return performance.now() - started;
}

test('a typed array or a buffer where a small value belongs is refused by its kind and length, its items unread', () => {
  // Describing the value walked its keys (its 50 million items) before
  // refusing it: 5-9 s. A message that gives kind and length was written
  // without reading an item; the times are logged, not asserted.
  const big = new Uint8Array(50e6);
  const said = 'a Uint8Array of 50,000,000 items';
  const ms = [];
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  const s = new logs.RealLogSession(FLASER);
  const cases = [
    [() => core.twoCellPreset(big), 'invalid preset'],
    [() => core.forwardDensity(big, 2, undefined), 'invalid z'],
    [() => core.forwardDensity(2, 2, big), 'invalid params'],
    [() => core.runCellFilter(big, 0.3, 0.5, 12, new Uint8Array([1]), true), 'invalid p_occ'],
    [() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1]), big), 'invalid'],
    [() => core.zipMapPair(big, new Uint8Array(1), 'image: m.pgm\n'), 'invalid name'],
    [() => core.zipMapPair('m', new Uint8Array(1), big), 'invalid yaml'],
    [() => core.jointPosterior(big), 'invalid joint query'],
    [() => new core.MapWeaver(big), 'invalid settings'],
    [() => new core.MapWeaver({ laps: 1, scene: big }), 'invalid settings.scene'],
    [() => new core.DoorwayTrap(big), 'invalid scene'],
    [() => new core.SensorFusion({ lidar: big }, undefined), 'invalid scene.lidar'],
    [() => new core.InverseWorkbench(big), 'invalid seed'],
    [() => w.advance(big), 'invalid scans'],
    [() => w.cellInfo(0, 0, big), 'invalid row'],
    [() => w.setPerson(big), 'invalid person'],
    [() => w.stagePane(0, big), 'invalid panes[0]'],
    [() => w.stagePane(0, { clamp: big }), 'invalid panes[0].clamp'],
    [() => s.configure(big), 'invalid settings'],
    [() => s.read(big), 'invalid maxScans'],
    [() => s.zoomAt(0, 0, big, 2), 'invalid y'],
    [() => s.exportStem(0, big), 'invalid'],
  ];
  for (const [f, field] of cases) ms.push(refusalMs(f, field, said));
  // Another kind of view in a bytes parameter is named as such.
  ms.push(refusalMs(() => new logs.RealLogSession(new Float64Array(5e6)), 'invalid bytes', 'a Float64Array of 5,000,000 items'));
  ms.push(refusalMs(() => core.zipMapPair('m', new Int16Array(5e6), 'image: m.pgm\n'), 'invalid pgm', 'an Int16Array of 5,000,000 items'));
  console.log(`refusals of large typed arrays: the slowest took ${Math.round(Math.max(...ms))} ms`);
  assert.equal(w.advance(1), 1, 'the run maps on');
  assert.equal(s.read(Infinity).scans, 5, 'the session reads on');
  w.free();
  s.free();
});

test('an ArrayBuffer or a DataView is no settings or scene object: refused by name, not read as {}', () => {
  const buffer = new ArrayBuffer(16);
  const view = new DataView(new ArrayBuffer(8));
  refuses(() => new core.MapWeaver(buffer), 'invalid settings', 'an ArrayBuffer of 16 bytes');
  refuses(() => new core.MapWeaver({ laps: 1, scene: view }), 'invalid settings.scene', 'a DataView of 8 bytes');
  refuses(() => new core.DoorwayTrap(view), 'invalid scene', 'a DataView of 8 bytes');
  refuses(() => new core.SensorFusion(buffer, undefined), 'invalid scene', 'an ArrayBuffer of 16 bytes');
  refuses(() => new core.SensorFusion(undefined, { sonar_p_occ: buffer }), 'invalid models.sonar_p_occ', 'an ArrayBuffer');
  refuses(() => core.forwardDensity(2, 2, view), 'invalid params', 'a DataView of 8 bytes');
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  refuses(() => w.stagePane(1, buffer), 'invalid panes[1]', 'an ArrayBuffer of 16 bytes');
  refuses(() => w.stagePane(1, { model: view }), 'invalid panes[1].model', 'a DataView');
  w.free();
  const s = new logs.RealLogSession(FLASER);
  refuses(() => s.configure(view), 'invalid settings', 'a DataView of 8 bytes');
  refuses(() => s.configure({ clamp: buffer }), 'invalid settings.clamp', 'an ArrayBuffer of 16 bytes');
  // Bytes parameters take a Uint8Array or an ArrayBuffer, as before.
  const bytes = FLASER.buffer.slice(FLASER.byteOffset, FLASER.byteOffset + FLASER.byteLength);
  assert.equal(new logs.RealLogSession(bytes).read(Infinity).scans, 5);
  s.open(new Uint8Array(FLASER), 'again.log');
  assert.equal(s.read(Infinity).scans, 5);
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1, 0, 1]).buffer, true).steps.length, 3);
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, view, true), 'invalid readings', 'a DataView of 8 bytes');
  s.free();
});

test('nonsense the core took without a word is refused by name', () => {
  // A negative expected range gave a density (0.0167).
  refuses(() => core.forwardDensity(2, -1, undefined), 'invalid z_star: -1');
  assert.ok(core.forwardDensity(2, 2, undefined) > 0);
  // A third pane was dropped unread.
  refuses(() => new core.MapWeaver({ panes: [{}, {}, {}] }), 'invalid settings.panes', 'an array of 3', 'exactly 2');
  refuses(() => new core.MapWeaver({ panes: [{}] }), 'invalid settings.panes');
  // Frame times that are no durations were ignored.
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  for (const [bad, shown] of [[NaN, 'NaN'], [-1, '-1'], [Infinity, 'inf'], [-Infinity, '-inf']]) {
    refuses(() => w.recordFrameMs(bad), `invalid ms: ${shown}`);
  }
  w.recordFrameMs(0);
  w.recordFrameMs(16.5);
  w.free();
  // A zoom about no point was taken as one about the centre.
  const s = new logs.RealLogSession(FLASER);
  s.read(Infinity);
  s.buildSlice(Infinity);
  s.setViewSize(0, 100, 80);
  const before = JSON.stringify(s.view(0));
  refuses(() => s.zoomAt(0, NaN, NaN, 2), 'invalid x: NaN');
  refuses(() => s.zoomAt(0, 5, Infinity, 2), 'invalid y: inf');
  assert.equal(JSON.stringify(s.view(0)), before, 'a refused zoom moved nothing');
  s.zoomAt(0, 50, 40, 2);
  assert.notEqual(JSON.stringify(s.view(0)), before);
  s.free();
});

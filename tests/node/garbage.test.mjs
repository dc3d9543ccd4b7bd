// Garbage from the JavaScript side of the glue: what a page actually
// passes — strings from attributes, undefined, objects where numbers
// belong, negative and fractional counts — must come back as an Error
// naming the field (or be a harmless no-op), never as a dead module, and
// the widget objects must keep working. Complements tests/wasm_garbage.rs,
// which calls the same bindings from Rust. Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import { loadCore } from '../../scripts/lib/load-core.mjs';
import { refuses } from './refuses.mjs';

const { core } = await loadCore();
/** The real-log module of the core (`RealLogSession`), loaded on its own as the page does. */
const logs = (await loadCore({ logs: true })).core;
// The W1 benchmark's log parser ships only in the bench build.
const bench = (await loadCore({ bench: true })).core;

test('the cell filter refuses strings, undefined and objects for its numbers', () => {
  refuses(() => core.runCellFilter('0.7x', 0.3, 0.5, 12, new Uint8Array([1]), true), 'p_occ');
  refuses(() => core.runCellFilter(0.7, undefined, 0.5, 12, new Uint8Array([1]), true), 'p_free');
  refuses(() => core.runCellFilter(0.7, 0.3, {}, 12, new Uint8Array([1]), true), 'prior');
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, '-3', new Uint8Array([1]), true), 'clamp', '-3');
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1, 9]), true), 'readings[1]');
  // Numbers are read as JavaScript holds them: a numeric string is no
  // number (the glue's coercion would call valueOf on any object).
  refuses(() => core.runCellFilter('0.7', 0.3, 0.5, 12, new Uint8Array([1]), true), 'invalid p_occ: "0.7" (expected a number)');
  const t = core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1, 1, 0]), true);
  assert.equal(t.steps.length, 3);
  // True or false is a boolean: the glue's coercion read 1 and "no" as
  // true, 0 and an object as false (calling its valueOf on the way).
  for (const bad of [1, 0, 'no', undefined, null, {}, { valueOf: () => true }]) {
    refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array([1]), bad), 'invalid subtract_prior', 'expected true or false');
  }
  // Readings are a Uint8Array or an array of 0s and 1s; the glue's own
  // copy read '101' as three bytes and 5 as none, and wrapped 256 to 0.
  for (const bad of ['101', 5, undefined, null, {}]) {
    refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, bad, true), 'invalid readings', 'Uint8Array');
  }
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, [1, 256], true), 'readings[1]', '256');
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, [1, 0], true).steps.length, 2);
  // The readings' budget is checked on the length, before the copy: a
  // hundred million bytes panicked the core (3.2 GB of rows).
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array(1e8), true), 'invalid readings', '100000000 readings', 'at most 10000');
  refuses(() => core.runCellFilter(0.7, 0.3, 0.5, 12, new Array(10_001).fill(1), true), 'invalid readings', '10001 readings');
  assert.equal(core.runCellFilter(0.7, 0.3, 0.5, 12, new Uint8Array(10_000), true).steps.length, 10_000);
});

test('Map Weaver refuses attribute-like garbage and keeps mapping', () => {
  refuses(() => new core.MapWeaver('3 laps'), 'settings');
  refuses(() => new core.MapWeaver({ laps: 0 }), 'laps');
  refuses(() => new core.MapWeaver({ laps: '3' }), 'settings');
  refuses(() => new core.MapWeaver({ panes: [{ clamp: -1 }, {}] }), 'panes[0].clamp');
  refuses(() => new core.MapWeaver({ seed: 'x' }), 'settings.seed');
  refuses(() => new core.MapWeaver([1]), 'settings', '[1]', 'expected an object');
  refuses(() => new core.MapWeaver({ training: { triplets: 1e6, epochs: 200 } }), 'training.triplets x training.epochs', '5000000');
  const w = new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } });
  assert.equal(w.advance(3), 3);
  const before = JSON.stringify(w.readout());
  // stagePane is the one way to turn a knob: a patch of the pane's settings.
  refuses(() => w.stagePane(0, { clamp: 'high' }), 'invalid panes[0].clamp', '"high"', 'expected f64');
  refuses(() => w.stagePane(0, { clamp: NaN }), 'panes[0].clamp', 'NaN');
  refuses(() => w.stagePane(0, { clamp: null }), 'panes[0].clamp', 'null');
  refuses(() => w.stagePane(1, { strength: '11' }), 'panes[1].strength', '11');
  refuses(() => w.stagePane(1, { strength: 11 }), 'panes[1].strength', '11');
  refuses(() => w.stagePane(1, { strenght: 2 }), 'panes[1]', 'unknown field "strenght"', 'strength');
  for (const bad of [undefined, null, 3, 'clamp', [{ clamp: 3 }]]) {
    refuses(() => w.stagePane(0, bad), 'invalid panes[0]', 'expected an object of named settings');
  }
  // A knob's name that is not a string is refused with the names it may take.
  for (const bad of [42, null, ['x'], true]) {
    const m = refuses(() => w.stagePane(0, { model: bad }), 'invalid panes[0].model', '"hand-crafted", "learned"');
    assert.ok(!m.includes('memory access'), m);
    refuses(() => w.stagePane(1, { pose: bad }), 'invalid panes[1].pose', '"oracle", "dead-reckoning"');
  }
  refuses(() => w.stagePane(0, { model: 'magic' }), 'panes[0].model', 'magic');
  refuses(() => w.stagePane(1, { pose: '' }), 'panes[1].pose');
  refuses(() => w.stagePane(2, { clamp: 3 }), 'pane');
  // A refused field refuses the whole patch: the clamp beside it is not taken.
  refuses(() => w.stagePane(0, { clamp: 3, beams: 7 }), 'panes[0].beams', '7');
  for (const bad of [1, 'on', undefined, null, { valueOf: () => true }]) {
    refuses(() => w.setPerson(bad), 'invalid person', 'expected true or false');
  }
  // Indices are whole numbers in range: the glue once wrapped -1 and
  // 2^32 and truncated 1.5 to a valid pane.
  for (const pane of [-1, 1.5, 2 ** 32, 1.5e10, NaN, Infinity, 'left', undefined]) {
    refuses(() => w.pixels(pane), 'pane');
    refuses(() => w.overlay(pane), 'pane');
    refuses(() => w.stagePane(pane, { strength: 1 }), 'pane');
    refuses(() => w.exportMap(pane), 'pane');
  }
  refuses(() => w.cellInfo(0, 0.5, 0), 'col', '0.5');
  refuses(() => w.cellInfo(0, 0, 'x'), 'row', '"x"');
  refuses(() => w.cellInfo(0, 0, NaN), 'row', 'NaN');
  for (const n of [-1, 0.5, NaN, 'many']) refuses(() => w.advance(n), 'scans');
  refuses(() => w.recordFrameMs('slow'), 'invalid ms', '"slow"');
  refuses(() => w.recordFrameMs(-1), 'invalid ms: -1');
  refuses(() => w.recordFrameMs(NaN), 'invalid ms: NaN');
  assert.equal(JSON.stringify(w.readout()), before, 'refused calls changed nothing');
  assert.equal(w.cellInfo(0, -1, 0), null);
  assert.equal(w.cellInfo(0, 0, 1e12), null);
  assert.equal(w.advance(0), 0);
  assert.equal(w.advance(2), 2, 'still maps');
  w.stagePane(0, { model: 'learned' });
  w.stagePane(1, { pose: 'dead-reckoning', clamp: 4 });
  const panes = w.readout().panes;
  assert.deepEqual([panes[0].model, panes[1].pose, panes[1].clamp], ['learned', 'dead-reckoning', 4]);
  // The fields a patch leaves out keep their values.
  assert.equal(panes[1].model, JSON.parse(before).panes[1].model);
  assert.equal(w.advance(1), 1);
  assert.ok(w.exportMap(1).pgm.length > 0);
  assert.ok(w.pixels(1) > 0);
  w.free();
});

test('the doorway trap, the fusion widget and the log reader refuse garbage by name', () => {
  refuses(() => new core.DoorwayTrap({ prior: 'half' }), 'scene');
  refuses(() => new core.DoorwayTrap({ prior: 0 }), 'prior');
  refuses(() => new core.DoorwayTrap({ sonar: { beta_deg: 180 } }), 'sonar.beta_deg');
  refuses(() => new core.DoorwayTrap({ seed: 'seven' }), 'scene.seed');
  refuses(() => new core.DoorwayTrap([]), 'invalid scene: [] (expected an object of named settings)');
  refuses(() => new core.DoorwayTrap({ resolution: 0.0015 }), 'width x height', '250000');
  const t = new core.DoorwayTrap({ seed: 5 });
  refuses(() => t.cellInfo(-1, 0), 'cell', '-1');
  refuses(() => t.cellInfo(0.5, 0), 'cell', '0.5');
  for (const bad of [undefined, 0, {}, ['map']]) refuses(() => t.exportMap(bad), 'invalid map', '"sweep" or "map"');
  refuses(() => t.exportMap('both'), 'map', 'both');
  for (const bad of [-1, 0.5, NaN, 'all']) refuses(() => t.mapRun(bad), 'maxFlips');
  assert.ok(t.mapRun(Infinity) > 0, 'Infinity runs the climb to its end');
  assert.equal(t.mapStep(), null);
  assert.ok(t.exportMap('map').pgm.length > 0);
  t.free();
  refuses(() => core.jointPosterior([]), 'joint query', '[]');
  refuses(() => core.twoCellPreset('diagonal'), 'invalid preset', 'side, collinear, apart');
  refuses(() => core.twoCellPreset(7), 'invalid preset', 'side, collinear, apart');
  refuses(() => core.forwardDensity(1, 2, [1, 2]), 'params');
  refuses(() => core.forwardDensity(1, 2, { z_max: 'far' }), 'params.z_max');

  refuses(() => new core.SensorFusion({ lidar: { beams: -5 } }, undefined), 'scene.lidar.beams');
  refuses(() => new core.SensorFusion(undefined, { clamp: 'x' }), 'models.clamp');
  refuses(() => new core.SensorFusion({ step: 0.00041, sonar: { count: 256, sub_rays: 256 } }, undefined),
    'steps x sonar.count x sonar.sub_rays', '2000000');
  const f = new core.SensorFusion(undefined, undefined);
  for (const beams of ['many', -1, 0.5, Infinity, NaN, null, 3000]) {
    refuses(() => f.setLidarBeams(beams), 'lidar.beams');
  }
  for (const bad of [0, undefined, null, { key: 'max' }]) {
    refuses(() => f.render(bad), 'invalid map', '"sonar"');
    refuses(() => f.exportMap(bad), 'invalid map', '"sonar"');
  }
  refuses(() => f.render('top'), 'map', 'top');
  assert.ok(f.step());
  assert.ok(f.render('max') > 0);
  f.free();

  refuses(() => bench.LaserLog.fromBytes(new TextEncoder().encode('<html>\n')), 'line 1');
  for (const bad of [42, 'FLASER 1 2 0 0 0 0 0 0', undefined, {}, [70, 76]]) {
    refuses(() => bench.LaserLog.fromBytes(bad), 'invalid bytes', 'Uint8Array');
    refuses(() => new logs.RealLogSession(bad), 'invalid bytes', 'Uint8Array');
  }
  assert.equal(bench.LaserLog.fromBytes(new TextEncoder().encode('FLASER 3 1 2 3 0 0 0 0 0 0\n').buffer).scanCount, 1);
  refuses(() => bench.LaserLog.fromBytes(new Uint8Array([0x1f, 0x8b, 1, 2, 3])), 'line 1');
  const s = new logs.RealLogSession(new TextEncoder().encode('FLASER 3 1 2 3 0 0 0 0 0 0\n'));
  s.read(10);
  refuses(() => s.configure({ resolution: 'fine' }), 'settings.resolution');
  refuses(() => s.configure([0.1]), 'settings');
  refuses(() => s.configure({ clamp: -1 }), 'clamp');
  refuses(() => s.configure({ lOcc: 1e39 }), 'lOcc');
  refuses(() => s.seek(1e6), 'scan');
  for (const bad of [-1, 0.5, NaN]) {
    refuses(() => s.seek(bad), 'scan');
    refuses(() => s.robotAt(0, bad), 'scan');
    refuses(() => s.buildSlice(bad), 'maxCells');
    refuses(() => s.cellAt(bad, 0, 0), 'pane');
  }
  assert.equal(s.cellAt(0, -1, 0), null);
  assert.equal(s.cellAt(0, 0, 2 ** 32), null);
  refuses(() => s.cellAt(0, 0.5, 0), 'col');
  assert.equal(s.buildSlice(Infinity).finished, true);
  for (const bad of [42, {}, ['m']]) refuses(() => s.exportMap(0, bad), 'invalid name');
  assert.match(s.exportMap(0, undefined).yaml, /^image: map\.pgm/);
  assert.match(s.exportMap(0, 'lab').yaml, /^image: lab\.pgm/);
  // The view: sizes, zooms and positions by name; what is drawn is the view's size.
  for (const bad of [0, -1, 0.5, NaN, 9000, '64']) refuses(() => s.setViewSize(0, bad, 10), 'width');
  refuses(() => s.setViewSize(0, 3000, 3000), 'width x height');
  for (const bad of [0, -2, NaN, Infinity]) refuses(() => s.zoomAt(0, 0, 0, bad), 'factor');
  refuses(() => s.panBy(0, NaN, 0), 'pan');
  refuses(() => s.cellAtView(0, NaN, 0), 'view position');
  s.setViewSize(0, 64, 48);
  assert.ok(s.renderView(0) > 0);
  assert.deepEqual([s.view(0).width, s.view(0).height], [64, 48]);
  assert.equal(s.cellAtView(0, -1e9, 0), null);
  s.free();
  const reading = new logs.RealLogSession(new TextEncoder().encode('FLASER 3 1 2 3 0 0 0 0 0 0\n'));
  for (const bad of [-1, 0.5, NaN, 'all']) refuses(() => reading.read(bad), 'maxScans');
  assert.equal(reading.read(Infinity).finished, true);
  reading.free();

  const pgm = new Uint8Array([1, 2, 3]);
  refuses(() => core.zipMapPair(42, pgm, 'image: x\n'), 'invalid name', '42');
  refuses(() => core.zipMapPair('m', [1, 2, 3], 'image: x\n'), 'invalid pgm', '[1,2,3]');
  refuses(() => core.zipMapPair('m', pgm, undefined), 'invalid yaml', 'undefined');
  assert.equal(core.zipMapPair('m', pgm, 'image: x\n').fileName, 'm.zip');
});

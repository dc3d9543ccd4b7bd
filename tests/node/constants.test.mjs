// The model values the widgets and the README state, against the core's
// (constants come from the core). The widgets take their bounds
// and presets from `constants()` once the core has loaded; what must be
// written before that (the cell filter's defaults, widgets/lib/defaults.js)
// and the README's attribute tables are checked here, so neither can say
// something the core does not. Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { loadCore } from '../../scripts/lib/load-core.mjs';
import { CELL_FILTER_DEFAULTS, MAP_WEAVER_LOG_DEFAULTS, MAP_WEAVER_MODELS, MAP_WEAVER_PANE_DEFAULTS } from '../../widgets/lib/defaults.js';

const { core } = await loadCore();
const k = core.constants();
const readme = fs.readFileSync(path.resolve(import.meta.dirname, '../../README.md'), 'utf8');

/** The README's table row of `attribute` in the section of `<tag>`: its cells. */
function row(tag, attribute) {
  const start = readme.indexOf(`### \`<${tag}>\``);
  assert.ok(start >= 0, `README has a section for <${tag}>`);
  const end = readme.indexOf('\n#', start + 4);
  const line = readme.slice(start, end < 0 ? undefined : end).split('\n').find((l) => l.startsWith(`| \`${attribute}\` |`));
  assert.ok(line, `README's <${tag}> table has a row for ${attribute}`);
  return line.split(' | ').map((c) => c.replace(/^\| /, '').replace(/ \|$/, ''));
}

/** README numbers use a typographic minus. */
const minus = (x) => String(x).replace('-', '−');

test('the cell filter’s defaults are the core’s worked example, in the widget and the README', () => {
  const w = k.cellFilter.workedExample;
  const expected = {
    'p-occ': w.pOcc.toFixed(2), 'p-free': w.pFree.toFixed(2), prior: w.prior.toFixed(2),
    readings: w.readings.map((r) => (r ? 'o' : 'f')).join(''), 'forget-l0': w.subtractPrior ? 'off' : 'on',
  };
  assert.deepEqual(CELL_FILTER_DEFAULTS, expected);
  for (const [name, value] of Object.entries(expected)) assert.equal(row('occgrid-cell-filter', name)[2], `\`${value}\``, name);
  // The core's worked example runs from the same preset.
  const run = core.workedExample();
  assert.deepEqual(run.steps.map((s) => (s.occupied ? 1 : 0)), w.readings);
  assert.equal(run.clamp, w.clamp);
});

test('the l0 lesson forgets the prior, from a prior its two answers sit around', () => {
  const l = k.cellFilter.l0Lesson;
  assert.equal(l.subtractPrior, false);
  const t = core.runCellFilter(l.pOcc, l.pFree, l.prior, l.clamp, new Uint8Array(0), true);
  // Symmetric in log odds within a tenth: alternating readings stay near l0.
  assert.ok(Math.abs((t.lOcc - t.l0) + (t.lFree - t.l0)) < 0.1, JSON.stringify(t));
  assert.ok(l.readings.every((r, i) => r === (i % 2 === 0 ? 1 : 0)));
});

test('the README’s ranges are the core’s limits', () => {
  const b = k.inverseWorkbench;
  const reading = row('occgrid-inverse-workbench', 'reading');
  assert.match(reading[1], new RegExp(`^0\\.2 to ${b.zMax} m `));
  assert.match(reading[3], new RegExp(`${b.zMax} m is the sensor's z_max`));
  assert.match(row('occgrid-inverse-workbench', 'density')[1], new RegExp(`^0 to ${b.maxDensity} `));

  const f = k.sensorFusion;
  const beams = row('occgrid-sensor-fusion', 'lidar-beams');
  assert.equal(beams[1], `1 to ${f.maxLidarBeams}`);
  assert.equal(beams[2], `\`${f.defaultLidarBeams}\``);

  const c = k.twoCellTable;
  assert.match(row('occgrid-doorway-trap', 'cells')[1], new RegExp(`ranges 0\\.1 to ${c.maxRange}, bearings ${minus(-c.halfConeDeg)} to ${c.halfConeDeg}\\)`));
  const z = row('occgrid-doorway-trap', 'reading');
  assert.match(z[1], new RegExp(`^0\\.1 to ${c.maxRange} m `));
  assert.match(z[3], new RegExp(`\\(${c.maxRange} = no echo\\)`));
  // The limits are the chapter's query's own.
  const q = core.chapterTwoCellQuery();
  assert.equal(q.model.z_max, c.maxRange);
  assert.equal(q.beta_deg / 2, c.halfConeDeg);
});

test('Map Weaver’s speed 1 is the apartment’s scan rate, as the README says', () => {
  const w = new core.MapWeaver(undefined);
  try {
    assert.equal(row('occgrid-map-weaver', 'speed')[3], `playback speed, × ${w.scanRate} scans per second`);
    const six = new core.MapWeaver({ scene: { scan_rate: 6 } });
    assert.equal(six.scanRate, 6);
    six.free();
  } finally {
    w.free();
  }
});

test('Map Weaver’s map and real-log defaults are the core’s, in the widget and the README', () => {
  const w = new core.MapWeaver(undefined);
  let panes;
  try {
    panes = w.readout().panes;
  } finally {
    w.free();
  }
  const sides = ['left', 'right'];
  sides.forEach((side, i) => {
    assert.equal(MAP_WEAVER_MODELS[side], panes[i].model, `${side}-model`);
    assert.equal(Number(MAP_WEAVER_PANE_DEFAULTS.clamp), panes[i].clamp, `${side}-clamp`);
    assert.equal(Number(MAP_WEAVER_PANE_DEFAULTS.strength), panes[i].strength, `${side}-strength`);
    assert.equal(Number(MAP_WEAVER_PANE_DEFAULTS.beta), panes[i].betaDeg, `${side}-beta`);
  });
  assert.equal(row('occgrid-map-weaver', 'left-model`, `right-model')[2], `\`${MAP_WEAVER_MODELS.left}\`, \`${MAP_WEAVER_MODELS.right}\``);
  for (const suffix of ['clamp', 'strength', 'beta']) {
    assert.equal(row('occgrid-map-weaver', `left-${suffix}\`, \`right-${suffix}`)[2], `\`${MAP_WEAVER_PANE_DEFAULTS[suffix]}\``, suffix);
  }

  // Written as the panel's link writes each setting (map-weaver.js, LOG_FIELDS).
  const d = core.LogMapSession.defaultSettings();
  const expected = {
    'log-resolution': String(d.resolution), 'log-range-cap': String(d.rangeCap), 'log-alpha': d.alpha.toFixed(2),
    'log-l-occ': d.lOcc.toFixed(2), 'log-l-free': d.lFree.toFixed(2), 'log-clamp': d.clamp.toFixed(1),
    'log-no-return-reach': String(d.noReturnReach), 'log-walls': String(d.walls), 'log-poses': String(d.poses), 'log-seed': String(d.seed),
  };
  assert.deepEqual(MAP_WEAVER_LOG_DEFAULTS, expected);
  for (const [name, value] of Object.entries(expected)) assert.equal(row('occgrid-map-weaver', name)[2], `\`${value}\``, name);
});

// The model values the widgets and the README state, against the core's:
// the core computes them, the widgets take their bounds, presets and
// defaults from `constants()` once it has loaded, and what must be written
// before that (widgets/lib/defaults.js) and the README's attribute tables
// are checked here, so neither can say something the core does not. Map
// Weaver's limits are also checked to be exactly where its session starts
// refusing. Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { loadCore } from '../../scripts/lib/load-core.mjs';
import { CELL_FILTER_DEFAULTS, MAP_WEAVER_LOG_DEFAULTS } from '../../widgets/lib/defaults.js';

const { core } = await loadCore();
/** The real-log module of the core (`RealLogSession`), loaded on its own as the page does. */
const logs = (await loadCore({ logs: true })).core;
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
  const shortest = (x) => String(x).replace('.', '\\.');
  assert.match(reading[1], new RegExp(`^${shortest(k.limits.inverseWorkbench.reading.min)} to ${b.zMax} m `));
  assert.match(reading[3], new RegExp(`${b.zMax} m is the sensor's z_max`));
  assert.match(row('occgrid-inverse-workbench', 'density')[1], new RegExp(`^0 to ${b.maxDensity} `));

  const f = k.sensorFusion;
  const beams = row('occgrid-sensor-fusion', 'lidar-beams');
  assert.equal(beams[1], `1 to ${f.maxLidarBeams}`);
  assert.equal(beams[2], `\`${f.defaultLidarBeams}\``);

  const c = k.twoCellTable;
  const near = shortest(k.limits.twoCellTable.reading.min);
  assert.match(row('occgrid-doorway-trap', 'cells')[1], new RegExp(`ranges ${near} to ${c.maxRange}, bearings ${minus(-c.halfConeDeg)} to ${c.halfConeDeg}\\)`));
  const z = row('occgrid-doorway-trap', 'reading');
  assert.match(z[1], new RegExp(`^${near} to ${c.maxRange} m `));
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

/** A Map Weaver session's readout, the session freed. */
function weaverReadout(settings) {
  const w = new core.MapWeaver(settings);
  try {
    return w.readout();
  } finally {
    w.free();
  }
}

/** The message a refused Map Weaver settings object gives. */
function weaverRefusal(settings) {
  try {
    new core.MapWeaver(settings).free();
  } catch (e) {
    return e.message;
  }
  assert.fail(`accepted ${JSON.stringify(settings)}`);
}

/** "a, b or c", as the core lists choices in its messages. */
const orList = (items) => (items.length > 1 ? `${items.slice(0, -1).join(', ')} or ${items.at(-1)}` : String(items[0]));

test('Map Weaver’s defaults are the core’s chapter run, as the README says', () => {
  const d = k.mapWeaver.defaults;
  const r = weaverReadout(undefined);
  assert.equal(r.laps, d.laps);
  assert.equal(r.person, d.person);
  const fields = ['model', 'pose', 'clamp', 'strength', 'mapper', 'sensor', 'betaDeg', 'forgetL0'];
  d.panes.forEach((pane, i) => {
    for (const f of fields) assert.equal(r.panes[i][f], pane[f], `panes[${i}].${f}`);
    assert.equal(pane.beams, null, 'every beam');
    assert.equal(pane.resolution, null, 'the scene’s cell size');
  });

  const weaver = (attribute) => row('occgrid-map-weaver', attribute);
  assert.equal(weaver('seed')[2], `\`${d.seed}\``);
  assert.equal(weaver('laps')[2], `\`${d.laps}\``);
  assert.equal(weaver('person')[2], `\`${d.person ? 'on' : 'off'}\``);
  const both = (suffix) => weaver(`left-${suffix}\`, \`right-${suffix}`);
  assert.equal(both('model')[2], `\`${d.panes[0].model}\`, \`${d.panes[1].model}\``);
  // The other pane settings are the same on both sides.
  const written = { pose: 'pose', clamp: 'clamp', strength: 'strength', mapper: 'mapper', sensor: 'sensor', beta: 'betaDeg' };
  for (const [suffix, field] of Object.entries(written)) {
    assert.equal(d.panes[0][field], d.panes[1][field], field);
    assert.equal(both(suffix)[2], `\`${d.panes[0][field]}\``, suffix);
  }
  assert.equal(both('forget-l0')[2], `\`${d.panes[0].forgetL0 ? 'on' : 'off'}\``);
  assert.equal(both('resolution')[2], `the scene's (\`${r.panes[0].resolution}\`)`);
});

test('Map Weaver’s ranges in the README are the core’s limits and the chapter run’s choices', () => {
  const m = k.mapWeaver;
  const weaver = (attribute) => row('occgrid-map-weaver', attribute);
  const both = (suffix) => weaver(`left-${suffix}\`, \`right-${suffix}`);
  assert.equal(weaver('laps')[1], `1 to ${m.maxLaps}`);
  assert.equal(both('clamp')[1], `${m.clamp.min} to ${m.clamp.max} in steps of ${m.clamp.step}`);
  assert.equal(both('strength')[1], `${m.strength.min} to ${m.strength.max} in steps of ${m.strength.step}`);
  assert.equal(both('beta')[1], `${m.betaDeg.min} to ${m.betaDeg.max} in steps of ${m.betaDeg.step} (degrees)`);
  assert.equal(both('resolution')[1], orList(m.paneResolutions.map((r) => `\`${r}\``)));
  const r = weaverReadout(undefined);
  const divisors = r.choices.beams.map((c) => c.value).sort((a, b) => a - b);
  assert.equal(both('beams')[1], `a divisor of the LiDAR's beam count (${r.panes[0].beams}: ${divisors.join(', ')})`);
  const scans = weaver('scans')[3];
  assert.match(scans, new RegExp(`\\(${r.scansPerLap} per lap\\)`));
  assert.match(scans, new RegExp(`at most ${m.maxFastForwardWork.toLocaleString('en-US')} cell visits`));
});

test('Map Weaver’s published limits are where its core starts refusing', () => {
  const m = k.mapWeaver;
  const panes = (left) => ({ panes: [left, {}] });
  // At every limit: accepted (one session for the lows, one for the highs).
  const low = weaverReadout(panes({ strength: m.strength.min, clamp: m.clamp.min, betaDeg: m.betaDeg.min, resolution: m.paneResolutions.at(-1) }));
  assert.deepEqual([low.panes[0].strength, low.panes[0].clamp, low.panes[0].betaDeg], [m.strength.min, m.clamp.min, m.betaDeg.min]);
  const high = weaverReadout({ laps: m.maxLaps, ...panes({ strength: m.strength.max, clamp: m.clamp.max, betaDeg: m.betaDeg.max }) });
  assert.deepEqual([high.laps, high.panes[0].strength, high.panes[0].clamp, high.panes[0].betaDeg], [m.maxLaps, m.strength.max, m.clamp.max, m.betaDeg.max]);
  // A step past each, or between two steps: refused by name, with the range.
  const cases = [
    ['strength', m.strength], ['clamp', m.clamp], ['betaDeg', m.betaDeg],
  ];
  for (const [field, r] of cases) {
    for (const v of [r.min - r.step, r.max + r.step, r.min + r.step / 2]) {
      const e = weaverRefusal(panes({ [field]: v }));
      assert.ok(e.startsWith(`invalid panes[0].${field}: ${v} (`), e);
      assert.ok(e.endsWith(` from ${r.min} to ${r.max} in steps of ${r.step})`), e);
    }
  }
  assert.match(weaverRefusal({ laps: m.maxLaps + 1 }), new RegExp(`^invalid laps: ${m.maxLaps + 1} \\(expected 1 to ${m.maxLaps} laps\\)`));
  assert.match(weaverRefusal(panes({ resolution: 0.2 })), /^invalid panes\[0\]\.resolution: 0\.2 \(expected 0\.1 or 0\.05 metres per cell\)/);
});

test('Map Weaver offers the beam counts of the scene’s LiDAR, and refuses the others naming them', () => {
  const scene = { lidar: { beams: 48 } };
  const r = weaverReadout({ scene, panes: [{ beams: 16 }, { beams: 1 }] });
  const divisors = [48, 24, 16, 12, 8, 6, 4, 3, 2, 1];
  assert.deepEqual(r.choices.beams.map((c) => c.value), divisors);
  assert.deepEqual(r.choices.beams.map((c) => c.setting), [null, ...divisors.slice(1)]);
  assert.deepEqual([r.panes[0].beams, r.panes[1].beams], [16, 1]);
  for (const beams of [0, 5, 7, 36, 49, 60]) {
    assert.equal(weaverRefusal({ scene, panes: [{}, { beams }] }),
      `invalid panes[1].beams: ${beams} (expected a divisor of the LiDAR's beam count (48: ${orList([...divisors].reverse())}))`);
  }
});

test('Map Weaver’s real-log defaults are the core’s, in the widget and the README', () => {
  // Written as the panel's link writes each setting (map-weaver.js, LOG_FIELDS).
  const d = logs.RealLogSession.defaultSettings();
  const expected = {
    'log-resolution': String(d.resolution), 'log-range-cap': String(d.rangeCap), 'log-alpha': d.alpha.toFixed(2),
    'log-l-occ': d.lOcc.toFixed(2), 'log-l-free': d.lFree.toFixed(2), 'log-clamp': d.clamp.toFixed(1),
    'log-no-return-reach': String(d.noReturnReach), 'log-walls': String(d.walls), 'log-poses': String(d.poses), 'log-seed': String(d.seed),
  };
  assert.deepEqual(MAP_WEAVER_LOG_DEFAULTS, expected);
  for (const [name, value] of Object.entries(expected)) assert.equal(row('occgrid-map-weaver', name)[2], `\`${value}\``, name);
});

// The one table of the widgets' controls, the core's `constants().limits`
// (src/apps/limits.rs): every widget's attributes keep to exactly its
// ranges, steps and names (read as the widget reads them once its core has
// loaded, and as the sliders are built from them), and the core refuses a
// value a step past the table's ends where it has a limit there. Needs
// pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { loadCore } from '../../scripts/lib/load-core.mjs';
import { resolvedSpec } from '../../scripts/lib/custom-elements.mjs';
import { oneOf, probability, steps, whole } from '../../widgets/lib/attributes.js';
import { MAP_WEAVER_LOG_DEFAULTS } from '../../widgets/lib/defaults.js';

const { core } = await loadCore();
const logs = (await loadCore({ logs: true })).core;
const k = core.constants();
const L = k.limits;

/** The widget classes by tag, their modules imported with the DOM globals their top level touches stubbed. */
const widgets = await (async () => {
  const registry = new Map();
  globalThis.HTMLElement ??= class HTMLElement {};
  globalThis.customElements ??= { define: (tag, cls) => registry.set(tag, cls), get: (tag) => registry.get(tag) };
  const node = () => ({ style: {}, dataset: {}, classList: { add() {}, remove() {} }, setAttribute() {}, append() {}, prepend() {}, addEventListener() {} });
  globalThis.document ??= {
    querySelector: () => null, querySelectorAll: () => [], getElementsByTagName: () => [],
    createElement: node, head: node(), body: node(), addEventListener() {},
  };
  for (const file of ['cell-filter', 'doorway-trap', 'inverse-workbench', 'sensor-fusion', 'map-weaver']) {
    await import(`../../widgets/${file}.js`);
  }
  return registry;
})();

/** Tag `tag`'s attribute declarations, with the core's bounds applied as the widget applies them. */
const spec = (tag) => resolvedSpec(widgets.get(tag).attributeSpec, k);

/** True when attribute `s` takes `text`. */
const takes = (s, text, name = 'x') => {
  try {
    s.type.parse(String(text), name);
    return true;
  } catch {
    return false;
  }
};

/** Attribute `s` takes both ends of `r` and refuses a step past either and a half step in. */
function keepsTo(s, r, name) {
  assert.ok(takes(s, r.min) && takes(s, r.max), `${name} takes ${r.min} and ${r.max}`);
  for (const v of [r.min - r.step, r.max + r.step, r.min + r.step / 2]) assert.ok(!takes(s, v), `${name} refuses ${v}`);
}

test('the cell filter’s attributes keep to the core’s table', () => {
  const s = spec('occgrid-cell-filter');
  const t = L.cellFilter;
  for (const [attr, key] of [['p-occ', 'pOcc'], ['p-free', 'pFree'], ['prior', 'prior']]) {
    assert.equal(s[attr].type.describe, probability(t[key]).describe, attr);
    keepsTo(s[attr], t[key], attr);
  }
  assert.equal(s.clamp.type.describe, `${steps(t.clamp).describe} (log odds), or "off" for no clamp`);
  keepsTo(s.clamp, t.clamp, 'clamp');
  assert.ok(takes(s.clamp, 'off'));
});

test('the doorway trap’s and its two-cell table’s attributes keep to the core’s table', () => {
  const s = spec('occgrid-doorway-trap');
  const t = L.twoCellTable;
  assert.equal(s.scans.type.describe, whole(0, L.doorwayTrap.maxScans).describe);
  assert.ok(takes(s.scans, L.doorwayTrap.maxScans) && !takes(s.scans, L.doorwayTrap.maxScans + 1));
  assert.equal(s.reading.type.describe, steps(t.reading, 'm').describe);
  keepsTo(s.reading, t.reading, 'reading');
  assert.equal(s.prior.type.describe, steps(t.prior).describe);
  keepsTo(s.prior, t.prior, 'prior');
  // A cell's range keeps to the reading's.
  const c = k.twoCellTable;
  assert.ok(takes(s.cells, `${t.reading.min}, 0, ${t.reading.max}, ${c.halfConeDeg}`));
  assert.ok(!takes(s.cells, `${t.reading.min - t.reading.step}, 0, 2, 0`));
  assert.ok(!takes(s.cells, `1, 0, ${t.reading.max + t.reading.step}, 0`));
});

test('the inverse workbench’s attributes keep to the core’s table', () => {
  const s = spec('occgrid-inverse-workbench');
  const t = L.inverseWorkbench;
  assert.equal(t.reading.max, k.inverseWorkbench.zMax);
  assert.equal(t.density.max, k.inverseWorkbench.maxDensity);
  assert.equal(s.reading.type.describe, steps(t.reading, 'm').describe);
  assert.equal(s.density.type.describe, steps(t.density).describe);
  keepsTo(s.density, t.density, 'density');
  assert.ok(takes(s.reading, t.reading.min) && takes(s.reading, t.reading.max));
  assert.ok(!takes(s.reading, t.reading.min - t.reading.step) && !takes(s.reading, t.reading.max + t.reading.step));
});

test('sensor fusion’s beam counts are the core’s, within the scene’s cap', () => {
  const b = L.sensorFusion.beamSteps;
  assert.ok(b.length > 1 && b.every((n, i) => Number.isInteger(n) && n >= 1 && (i === 0 || n > b[i - 1])), String(b));
  assert.ok(b.includes(k.sensorFusion.defaultLidarBeams));
  assert.ok(b.at(-1) <= k.sensorFusion.maxLidarBeams);
  const s = spec('occgrid-sensor-fusion');
  for (const n of b) assert.ok(takes(s['lidar-beams'], n), String(n));
});

test('Map Weaver’s real-log attributes keep to the core’s table, names and menus', () => {
  const s = spec('occgrid-map-weaver');
  const r = L.realLog;
  const knobs = {
    'log-range-cap': ['rangeCap', 'm'], 'log-alpha': ['alpha', 'm'], 'log-l-occ': ['lOcc'], 'log-l-free': ['lFree'],
    'log-clamp': ['clamp'], 'log-no-return-reach': ['noReturnReach', 'm'],
  };
  for (const [attr, [key, unit]] of Object.entries(knobs)) {
    assert.equal(s[attr].type.describe, steps(r[key], unit).describe, attr);
    keepsTo(s[attr], r[key], attr);
  }
  const menus = { 'log-resolution': 'resolutions', 'log-walls': 'walls', 'log-poses': 'poses', 'log-model': 'models' };
  for (const [attr, key] of Object.entries(menus)) {
    assert.equal(s[attr].type.describe, oneOf(r[key].map((c) => String(c.value))).describe, attr);
    assert.ok(!takes(s[attr], 'nonsense'), attr);
  }
  assert.equal(s['log-compare-model'].type.describe, oneOf(['none', ...r.models.map((c) => c.value)]).describe);
  assert.equal(s['log-seed'].type.describe, whole(0, r.maxSeed).describe);
  // The menus' words are the core's.
  assert.deepEqual(r.resolutions.map((c) => c.caption), ['2.5 cm', '5 cm', '10 cm', '20 cm']);
  assert.deepEqual(r.models.map((c) => [c.value, c.caption]), [
    ['hit-counting', 'hit counting (GMapping)'], ['log-odds', 'log odds (Table 9.2)'], ['hit-miss-odds', 'hit/miss odds (Cartographer)'],
  ]);
  assert.deepEqual(r.poses.map((c) => c.value), ['corrected', 'dead-reckoning', 'scan-matched', 'odometry', 'slam']);
  // Each menu lists the session's default first (the attributes' defaults,
  // widgets/lib/defaults.js, are checked against it in constants.test.mjs).
  const d = logs.RealLogSession.defaultSettings();
  assert.ok(takes(s['log-range-cap'], MAP_WEAVER_LOG_DEFAULTS['log-range-cap']));
  for (const [attr, key] of Object.entries({ 'log-walls': 'walls', 'log-poses': 'poses' })) {
    assert.equal(r[key][0].value, d[key], `${attr}: the default first`);
  }
  assert.equal(r.models[0].value, d.model);
});

test('the core refuses a value a step past the table’s ends where it has a limit there', () => {
  // The cell filter: a step past a probability's ends is 0 or 1.
  const w = k.cellFilter.workedExample;
  const run = (p) => core.runCellFilter(p.pOcc, p.pFree, p.prior, p.clamp, new Uint8Array([1, 0]), true);
  for (const key of ['pOcc', 'pFree', 'prior']) {
    const r = L.cellFilter[key];
    for (const v of [r.min, r.max]) run({ ...w, [key]: v });
    for (const v of [r.min - r.step, r.max + r.step]) assert.throws(() => run({ ...w, [key]: v }), undefined, `${key} ${v}`);
  }
  // The two-cell table's prior, likewise; its reading up to the sonar's z_max.
  const q = core.chapterTwoCellQuery();
  const t = L.twoCellTable;
  assert.equal(t.reading.max, q.model.z_max);
  for (const v of [t.prior.min, t.prior.max]) core.jointAnswer({ ...q, prior: v });
  for (const v of [t.prior.min - t.prior.step, t.prior.max + t.prior.step]) assert.throws(() => core.jointAnswer({ ...q, prior: v }));
  // The real log's range cap: the traversal's reach at the default resolution.
  const r = L.realLog;
  const reach = logs.RealLogSession.limits(logs.RealLogSession.defaultSettings().resolution).rangeCapMax;
  assert.ok(r.rangeCap.max <= reach && r.rangeCap.max + r.rangeCap.step > reach, `${r.rangeCap.max} of ${reach}`);
  // Evidence of the wrong sign a step past l_occ's least and l_free's largest.
  const session = new logs.RealLogSession(new Uint8Array(0));
  try {
    for (const key of ['alpha', 'lOcc', 'lFree', 'clamp', 'noReturnReach', 'rangeCap']) {
      for (const v of [r[key].min, r[key].max]) session.configure({ [key]: v, ...(key === 'noReturnReach' ? { rangeCap: r.rangeCap.max } : {}) });
    }
    for (const c of r.resolutions) session.configure({ resolution: c.value });
    assert.throws(() => session.configure({ lOcc: r.lOcc.min - r.lOcc.step }), /lOcc/);
    assert.throws(() => session.configure({ lFree: r.lFree.max + r.lFree.step }), /lFree/);
  } finally {
    session.free();
  }
});

test('the README’s real-log ranges are the core’s table', () => {
  const readme = fs.readFileSync(path.resolve(import.meta.dirname, '../../README.md'), 'utf8');
  const r = L.realLog;
  const row = (attr) => readme.split('\n').find((l) => l.startsWith(`| \`${attr}\` |`))?.split(' | ')[1];
  const minus = (x) => String(x).replace('-', '−');
  const range = (s, unit = '') => `${minus(s.min)} to ${minus(s.max)}${unit} in steps of ${s.step}`;
  assert.ok(row('log-range-cap').startsWith(range(r.rangeCap, ' m')), row('log-range-cap'));
  assert.ok(row('log-alpha').startsWith(range(r.alpha, ' m')));
  assert.ok(row('log-l-occ').startsWith(range(r.lOcc)));
  assert.ok(row('log-l-free').startsWith(range(r.lFree)));
  assert.ok(row('log-clamp').startsWith(range(r.clamp)));
  assert.ok(row('log-no-return-reach').startsWith(range(r.noReturnReach, ' m')));
  const values = r.resolutions.map((c) => `\`${c.value}\``);
  assert.equal(row('log-resolution'), `${values.slice(0, -1).join(', ')} or ${values.at(-1)}`);
});

test('the README’s ranges of the other widgets are the core’s table', () => {
  const readme = fs.readFileSync(path.resolve(import.meta.dirname, '../../README.md'), 'utf8');
  /** The range cell of `attribute`'s row in the section of `<tag>`. */
  const row = (tag, attribute) => {
    const start = readme.indexOf(`### \`<${tag}>\``);
    const end = readme.indexOf('\n#', start + 4);
    return readme.slice(start, end).split('\n').find((l) => l.startsWith(`| \`${attribute}\` |`)).split(' | ')[1];
  };
  const range = (s, unit = '') => `${s.min} to ${s.max}${unit} in steps of ${s.step}`;
  const f = L.cellFilter;
  assert.equal(row('occgrid-cell-filter', 'p-occ'), `probability, ${range(f.pOcc)}`);
  assert.equal(row('occgrid-cell-filter', 'p-free'), `probability, ${range(f.pFree)}`);
  assert.equal(row('occgrid-cell-filter', 'prior'), `probability, ${range(f.prior)}`);
  assert.equal(row('occgrid-cell-filter', 'clamp'), `${range(f.clamp)} (log odds), or \`off\``);
  const t = L.twoCellTable;
  assert.equal(row('occgrid-doorway-trap', 'scans'), `0 to ${L.doorwayTrap.maxScans}`);
  assert.equal(row('occgrid-doorway-trap', 'reading'), range(t.reading, ' m'));
  assert.equal(row('occgrid-doorway-trap', 'prior'), range(t.prior));
  const w = L.inverseWorkbench;
  assert.equal(row('occgrid-inverse-workbench', 'reading'), range(w.reading, ' m'));
  assert.equal(row('occgrid-inverse-workbench', 'density'), range(w.density));
});

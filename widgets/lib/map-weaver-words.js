// The words and number formats of Map Weaver's captions, readouts and
// links: what a model, a pose source or a mapper is called on screen and in
// the maps' text alternatives, how a pane or real-log setting is written
// back into a link, and how the core's numbers are printed.
import { fixed, grouped } from './ui.js';
import { invalidValue } from './attributes.js';
import { LOG_MODEL_FIELDS } from './log-models.js';

export const MODEL_NAMES = { 'hand-crafted': 'hand-crafted model (Table 9.2)', learned: 'learned model (§9.3)' };
export const POSE_NAMES = { oracle: 'pose oracle', 'dead-reckoning': 'dead reckoning' };
/** The same, as the maps' text alternatives say them (not the controls' labels). */
export const SPOKEN_MODELS = { 'hand-crafted': 'the hand-crafted inverse model of Table 9.2', learned: 'the inverse model learned in §9.3' };
export const SPOKEN_POSES = { oracle: 'at the true poses', 'dead-reckoning': 'at the dead-reckoned poses' };

/** How a map canvas is operated, for its text alternative. */
export const CURSOR_HINT = 'Gray is unknown, white free, black occupied. Arrow keys move a cursor cell whose values are read out below the maps.';
/** The hover line while no cell is pointed at. */
export const HOVER_HINT = 'Point at a cell (or focus a map and use the arrow keys) to read its log odds, probability and update count.';
export const GROUPS = ['data', 'playback', 'toggles', 'sliders', 'log-source', 'log-settings', 'export', 'link'];
/** Every pane attribute, per side, and the pane setting it sets. */
export const PANE_FIELDS = {
  model: 'model', pose: 'pose', clamp: 'clamp', strength: 'strength',
  mapper: 'mapper', sensor: 'sensor', beta: 'betaDeg', beams: 'beams', resolution: 'resolution', 'forget-l0': 'forgetL0',
};
/** The pane settings whose change rebuilds the pane from the scans so far. */
export const REBUILD_FIELDS = ['mapper', 'sensor', 'betaDeg', 'beams', 'resolution', 'forgetL0'];
/** How a link writes a pane setting back, as its attribute's default is written. */
export const orAbsent = (v) => (v === null || v === undefined ? null : String(v));
export const PANE_FORMATS = { forgetL0: (v) => (v ? 'on' : 'off'), beams: orAbsent, resolution: orAbsent };
export const formatPane = (field, v) => (PANE_FORMATS[field] ? PANE_FORMATS[field](v) : String(v));
export const MAPPER_NAMES = { traversal: 'ray traversal', sweep: 'every-cell sweep' };
/** The hover line's words for the core's `leaning` of a cell. */
export const LEANINGS = { unknown: 'unknown (at the prior)', occupied: 'leaning occupied', free: 'leaning free', even: 'even (p = 0.5)' };

/**
 * The real-log panel's attributes: the panel setting each sets, and how a
 * link writes the setting back (as the default is written, so that a
 * default stays out of the link). The ranges are the panel's controls'.
 */
export const LOG_FIELDS = {
  'log-resolution': { field: 'resolution', format: (v) => String(v) },
  'log-range-cap': { field: 'rangeCap', format: (v) => String(v) },
  'log-alpha': { field: 'alpha', format: (v) => fixed(v, 2) },
  'log-l-occ': { field: 'lOcc', format: (v) => fixed(v, 2) },
  'log-l-free': { field: 'lFree', format: (v) => fixed(v, 2) },
  'log-clamp': { field: 'clamp', format: (v) => fixed(v, 1) },
  'log-no-return-reach': { field: 'noReturnReach', format: (v) => String(v) },
  'log-walls': { field: 'walls', format: (v) => String(v) },
  'log-poses': { field: 'poses', format: (v) => String(v) },
  'log-seed': { field: 'seed', format: (v) => String(v) },
  ...LOG_MODEL_FIELDS,
};

/** A log's file name in the server's /datasets/: one name, no path. */
export const logName = {
  describe: 'the file name of a CARMEN log or a ROS 2 bag in the server’s /datasets/, such as "intel-corrected.log.gz" or "intel-perfect.mcap"',
  parse(text, name) {
    const w = text.trim();
    if (!/^[\w-][\w.-]*\.((log|clf|txt)(\.gz)?|mcap)$/i.test(w)) throw invalidValue(name, text, this.describe);
    return w;
  },
};

// Whole counts and one-decimal bits are written by `grouped`, which makes no
// number formatter (a formatter per call is slow, and the page's first one
// a long task on a phone); other numbers keep en-US formatting's three
// decimals.
export const count = (n) => (Number.isInteger(Number(n)) ? grouped(Number(n)) : Number(n).toLocaleString('en-US'));

/** Exercise 5's readout: how long the person's ghost took to fade at the pane's clamp and strength, and the recursion's time. */
export function ghostText(g) {
  const scans = (n) => `${count(n)} scan${n === 1 ? '' : 's'}`;
  const lingering = g.lingering ? `; ${count(g.lingering)} ghost cell${g.lingering === 1 ? '' : 's'} still at p ≥ 0.5` : '';
  const recursion = g.recursionScans === null || g.recursionScans === undefined
    ? ' (the learned model’s free evidence depends on the range: no single l_max / |l_free| to predict from)'
    : `. The recursion: l_max / |l_free| = ${fixed(g.recursionScans * -g.freeEvidence, 1)} / ${fixed(-g.freeEvidence, 2)} = ` +
      `${fixed(g.recursionScans, 1)} contradicting scans (${fixed(g.recursionSeconds, 2)} s)`;
  if (!g.faded) return `Ghost: none has faded back below p = 0.5 at this clamp and strength yet${lingering}${recursion}.`;
  return `Ghost fade at this clamp and strength (person gone → p < 0.5): slowest ${scans(g.longestScans)} (${fixed(g.longestSeconds, 2)} s) ` +
    `over ${count(g.faded)} cell${g.faded === 1 ? '' : 's'}, last ${scans(g.lastScans)} (${fixed(g.lastSeconds, 2)} s)${lingering}${recursion}.`;
}

/**
 * What the core says about the two maps against each other: how many
 * cells their exports differ in (exercise 6, with the line of Table 9.2
 * that parts the traversal from the sweep) and the drift of a map that
 * forgets l0 (exercise 8). Empty when there is nothing to compare.
 */
export function comparisonText(r) {
  const out = [];
  const d = r.difference;
  if (d) {
    out.push(`The two maps’ exports (free, occupied, unknown) differ in ${count(d.cells)} of ${count(d.of)} cells, ` +
      `${count(d.updatedByOne)} of them updated by one map only.`);
    const [a, b] = r.panes;
    if (a.mapper !== b.mapper) {
      out.push('Traversal and sweep part at Table 9.2’s line 1 (|φ − θk| > β/2: no information): the sweep gives a cell nothing ' +
        'when its centre lies more than β/2 off its nearest beam’s axis (β/2 = 0.5° for the thin LiDAR), the traversal updates every ' +
        'cell a beam’s raster crosses, whatever its offset; for a cone, the sweep paints the cone between the beams, which no raster crosses.');
    }
  }
  const drift = r.l0Drift;
  if (drift) {
    const side = drift.pane === 0 ? 'Left' : 'Right';
    const measured = drift.perUpdate === null || drift.perUpdate === undefined
      ? 'no cell inside the clamp to measure yet'
      : `measured ${signed(drift.perUpdate, 3)} per update (median over ${count(drift.cells)} cells inside the clamp)`;
    out.push(`${side} map forgets l0: every update adds the model’s own l0 = ${signed(drift.modelL0, 3)} on top of the other map’s; ${measured}.`);
  }
  return out.join(' ');
}

/**
 * What Map Weaver's copied link keeps, as its status line says it: in
 * real-log mode, the settings and a log of the server's datasets/, never a
 * file of the reader's own (the link cannot carry it), `panel` being the
 * real-log panel (its `dataset` the datasets/ log shown, `name` any log).
 */
export function linkKeeps(mode, panel) {
  if (mode !== 'log') return 'Link copied: it opens this page with both maps’ settings, replayed to this scan.';
  if (panel?.dataset) return `Link copied: it opens this page in real-log mode with ${panel.dataset} from the server’s datasets and these settings.`;
  if (panel?.name) {
    return `Link copied: it keeps the real-log settings but not ${panel.name}, a file on this computer that a link cannot carry: ` +
      'the link opens the panel with no log; open the file there again.';
  }
  return 'Link copied: it keeps the real-log settings; no log is loaded, so the link opens the panel with none.';
}
export const bits = (x) => grouped(x, 1);
export const signed = (x, d) => (x > 0 ? '+' : '') + fixed(x, d);
/** A cell size as the menu says it: 0.10, 0.05, 0.0125. */
export const metres = (m) => m.toLocaleString('en-US', { minimumFractionDigits: 2, maximumFractionDigits: 6 });

/** The two panes' attribute prefixes, in the core's pane order. */
export const SIDES = ['left', 'right'];
/**
 * A core refusal of a pane setting in the words of the attribute that set
 * it: "invalid panes[0].beams: 16 (…)" is "invalid left-beams: 16 (…)" to
 * an instructor who wrote `left-beams="16"`.
 */
export function inAttributeTerms(error) {
  const message = error && error.message ? error.message : String(error);
  const words = message.replace(/panes\[([01])\]\.(\w+)/g, (whole, k, field) => {
    const suffix = Object.keys(PANE_FIELDS).find((a) => PANE_FIELDS[a] === field);
    return suffix ? `${SIDES[Number(k)]}-${suffix}` : whole;
  });
  return words === message ? error : new Error(words);
}

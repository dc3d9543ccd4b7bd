// <occgrid-doorway-trap>: why a wide sonar cone closes an open door in an
// occupancy grid, and how MAP mapping keeps it open (Probabilistic Robotics
// Tables 9.1–9.3; SPEC §6, §7, §10.3, §10.5).
//
// Left, Table 9.1 swept literally over every cell with a 22° sonar and the
// inverse model of Table 9.2, one stop's scan at a time: a cone that
// straddles a door jamb paints its whole arc occupied, across the doorway.
// Right, the MAP hill climb of Table 9.3 on the same readings, one flip at a
// time: each flipped cell is marked, a bar chart shows how the flip changed
// each beam's log likelihood, and a curve shows the objective over flips.
// Below, the exact joint posterior of two cells in one cone against the
// product of their marginals, with the cells movable and the reading
// adjustable. Every number comes from the wasm core; this module draws,
// lays out and forwards input.
//
// Attributes (see `attributeSpec` below and the README's "Embedding"):
// seed, scene, autoplay, scans, flips, arrangement, cells, reading, prior,
// map-width, controls.
import { loadCore } from './lib/core.js';
import { COLORS, barChart, lineChart } from './lib/chart.js';
import { downloadMapPair } from './lib/export.js';
import {
  el, slider, button, showError, clearError, hiDpiCanvas, drawMap,
  whenVisible, frameLoop, prefersReducedMotion, fixed, showPlaying,
} from './lib/ui.js';
import {
  applyControls, controlGroups, flag, formatControls, invalidValue, jsonObject, number, oneOf, whole,
} from './lib/attributes.js';
import { copyLinkControl, firstConnection } from './lib/state.js';

/** Sweep scans and MAP flips per second while playing. */
const SCANS_PER_SECOND = 1.5;
const FLIPS_PER_SECOND = 3;
/** Largest drawn map, CSS pixels. */
const MAX_CSS_WIDTH = 460;
const TRUTH_COLOR = COLORS.series[3];
const SET_COLOR = COLORS.series[1];
const CLEARED_COLOR = COLORS.series[2];
const CURRENT_COLOR = '#f2b400';
const LOWERED_COLOR = COLORS.series[1];
const POSE_COLOR = COLORS.series[1];

/** Cell arrangements of the two-cell table (range in metres, bearing in degrees). */
const ARRANGEMENTS = {
  collinear: [{ range: 2.0, bearing_deg: 0 }, { range: 2.5, bearing_deg: 0 }],
  apart: [{ range: 2.0, bearing_deg: -7 }, { range: 1.2, bearing_deg: 7 }],
};
/** The diagram's reach, metres, and the drag limits. */
const DIAGRAM_RANGE = 3.1;
/** The two-cell diagram, CSS pixels: the cone lies on its side, sensor at the left. */
const DIAGRAM_W = 440;
const DIAGRAM_H = 200;
const MIN_RANGE = 0.1;
const MAX_RANGE = 3.0;

/** The cone's half-width in the two-cell diagram, degrees (a 22° sonar). */
const HALF_CONE_DEG = 11;
const GROUPS = ['playback', 'arrangements', 'sliders', 'export', 'link'];
const HOVER_HINT = 'Point at a cell (or focus a map and use the arrow keys) to read it.';
const MAP_HINT = 'Arrow keys move a cursor cell whose values are read out below the maps.';

/** The `cells` attribute: "rangeA,bearingA,rangeB,bearingB" (metres, degrees). */
const cellsType = {
  describe: `four numbers "rangeA, bearingA, rangeB, bearingB": ranges from ${MIN_RANGE} to ${MAX_RANGE} m, bearings from -${HALF_CONE_DEG} to ${HALF_CONE_DEG}°`,
  parse(text, name) {
    const v = text.split(/[\s,;]+/).filter(Boolean).map(Number);
    const ok = v.length === 4 && v.every(Number.isFinite) &&
      [v[0], v[2]].every((r) => r >= MIN_RANGE && r <= MAX_RANGE) &&
      [v[1], v[3]].every((b) => Math.abs(b) <= HALF_CONE_DEG);
    if (!ok) throw invalidValue(name, text, this.describe);
    return [{ range: v[0], bearing_deg: v[1] }, { range: v[2], bearing_deg: v[3] }];
  },
};

const bits = (occupied) => occupied.map((o) => (o ? '1' : '0')).join(' ');

class DoorwayTrapElement extends HTMLElement {
  static attributeSpec = {
    seed: { type: whole(0, Number.MAX_SAFE_INTEGER), doc: 'seed of the sonar readings’ noise; absent: the chapter’s' },
    scene: { type: jsonObject('{"prior": 0.3}'), doc: 'fields of the doorway scene to override (the core checks each); absent: the chapter’s room and door' },
    autoplay: { type: flag(), default: 'on', doc: 'play both halves when first scrolled into view (never under prefers-reduced-motion)' },
    scans: { type: whole(0, 4096), default: '0', doc: 'sweep scans done before the first frame' },
    flips: { type: whole(0, 100_000), default: '0', doc: 'MAP flips done before the first frame (the climb stops at its local maximum)' },
    arrangement: { type: oneOf(['side', 'collinear', 'apart']), default: 'side', doc: 'the two cells of the two-cell table: side by side, one behind the other, or apart' },
    cells: { type: cellsType, doc: 'the two cells placed by hand, "rangeA, bearingA, rangeB, bearingB" (metres, degrees); overrides arrangement' },
    reading: { type: number(0.1, 3, { step: 0.01, unit: 'm' }), default: '2.00', doc: 'the two-cell table’s reading z, metres (3 = no echo)' },
    prior: { type: number(0.05, 0.95, { step: 0.05 }), default: '0.50', doc: 'the two-cell table’s prior occupancy p₀' },
    'map-width': { type: whole(120, 1200), default: String(MAX_CSS_WIDTH), doc: 'largest width of each map, CSS pixels' },
    controls: { type: controlGroups(GROUPS), default: 'all', doc: 'control groups shown: playback (step, play, reset of both halves), arrangements, sliders (reading, prior), export, link' },
  };

  static observedAttributes = Object.keys(DoorwayTrapElement.attributeSpec);

  constructor() {
    super();
    this.trap = null;
    this.playing = { sweep: false, map: false };
    this.lastFlip = null;
    this.lastScan = null;
    this.query = null;
    this.cursor = null; // { key, ix, iy }: the keyboard cursor on a map
    this.movingCell = 1; // which two-cell point the arrow keys move (0 = A, 1 = B)
  }

  async connectedCallback() {
    if (!firstConnection(this, DoorwayTrapElement.attributeSpec)) return;
    this.values = this.attrs.read();
    this.build();
    applyControls(this, this.values.controls);
    try {
      ({ core: this.core, memory: this.memory } = await loadCore());
    } catch (e) {
      showError(this, e, 'could not load the core: ');
      return;
    }
    this.create();
    this.initTwoCell();
    whenVisible(this, () => {
      if (this.values.autoplay && !prefersReducedMotion() && this.trap) {
        this.play('sweep');
        this.play('map');
      }
    });
  }

  disconnectedCallback() {
    this.pause('sweep');
    this.pause('map');
  }

  attributeChangedCallback(name) {
    if (!this.built) return;
    const before = this.values;
    this.values = this.attrs.read();
    const key = (v) => JSON.stringify(v instanceof Set ? [...v] : v);
    if (key(this.values[name]) === key(before[name])) return;
    if (name === 'controls') applyControls(this, this.values.controls);
    else if (name === 'map-width') {
      for (const p of Object.values(this.panes)) p.cssW = 0;
      this.layout();
    } else if (!this.core) return;
    else if (['seed', 'scene', 'scans', 'flips'].includes(name)) this.create();
    else if (['arrangement', 'cells', 'reading', 'prior'].includes(name)) this.initTwoCell();
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    const v = this.values;
    const q = this.query;
    const custom = this.arrangement === 'custom' && q;
    return {
      seed: v.seed, scene: v.scene ? JSON.stringify(v.scene) : null,
      autoplay: this.playing.sweep || this.playing.map ? 'on' : 'off',
      scans: this.report ? this.report.scansDone : v.scans,
      flips: this.state ? this.state.flips.length : v.flips,
      arrangement: custom ? null : this.arrangement,
      cells: custom ? q.cells.map((c) => `${fixed(c.range, 2)},${fixed(c.bearing_deg, 1)}`).join(',') : null,
      reading: q ? q.readings[0].toFixed(2) : null,
      prior: q ? q.prior.toFixed(2) : null,
      'map-width': v['map-width'],
      controls: formatControls(v.controls, GROUPS),
    };
  }

  // ---- Layout ----

  build() {
    const pane = (key, title, note, exportLabel, controls) => {
      const canvas = el('canvas', {
        class: 'occgrid-map doorway-trap-canvas', role: 'img', tabindex: 0,
        'aria-label': `${title} map of the doorway scene. ${MAP_HINT}`,
      });
      const status = el('p', { class: 'occgrid-readout doorway-trap-status', 'aria-live': 'polite' }, 'Loading…');
      const door = el('p', { class: 'occgrid-readout doorway-trap-door' });
      const exportButton = button('Export map', () => this.exportMap(key), {
        name: `export-${key}`, title: `${exportLabel} as a ROS map_server PGM + YAML pair`,
      });
      // The spoken name starts with the visible text (WCAG 2.5.3).
      exportButton.setAttribute('aria-label', `Export map (${exportLabel.replace(/^Export the /, '')})`);
      const root = el('figure', { class: `doorway-trap-pane doorway-trap-${key}`, dataset: { map: key } },
        el('figcaption', {}, el('strong', {}, title), ' ', el('span', { class: 'doorway-trap-note' }, note)),
        el('div', { class: 'occgrid-controls doorway-trap-buttons', dataset: { controls: 'playback' } }, controls),
        canvas, status, door,
        el('div', { class: 'doorway-trap-foot', dataset: { controls: 'export' } }, exportButton));
      canvas.addEventListener('pointermove', (ev) => this.hover(key, ev));
      canvas.addEventListener('pointerleave', () => this.hover(key, null));
      canvas.addEventListener('keydown', (ev) => this.keyCursor(key, ev));
      canvas.addEventListener('focus', () => {
        if (!this.cursor || this.cursor.key !== key) this.moveCursor(key, 0, 0);
      });
      canvas.addEventListener('blur', () => {
        this.cursor = null;
        this.draw();
      });
      return { key, canvas, status, door, root };
    };

    this.sweepPlay = button('Play', () => this.toggle('sweep'), { name: 'sweep-play', pressed: false });
    this.mapPlay = button('Play', () => this.toggle('map'), { name: 'map-play', pressed: false });
    const sweepStep = button('Next scan', () => { this.pause('sweep'); this.sweepStep(); this.draw(); }, { name: 'sweep-step' });
    const mapStep = button('Step', () => { this.pause('map'); this.mapStep(); this.draw(); }, { name: 'map-step' });
    for (const [b, what] of [[this.sweepPlay, 'the sweep'], [this.mapPlay, 'the MAP climb']]) b.setAttribute('aria-label', `Play ${what}`);
    mapStep.setAttribute('aria-label', 'Step the MAP climb by one flip');
    this.panes = {
      sweep: pane('sweep', 'Table 9.1, swept', '· every cell, the nearest 22° cone, Table 9.2', 'Export the swept map', [
        sweepStep, this.sweepPlay,
        button('Reset', () => { this.pause('sweep'); this.trap?.sweepReset(); this.lastScan = null; this.draw(); }, { name: 'sweep-reset', title: 'Back to the empty grid' }),
      ]),
      map: pane('map', 'MAP, hill climbing', '· Table 9.3, one flip at a time', 'Export the MAP map', [
        mapStep, this.mapPlay,
        button('Reset', () => { this.pause('map'); this.trap?.mapReset(); this.lastFlip = null; this.draw(); }, { name: 'map-reset', title: 'Back to the all-free start' }),
      ]),
    };
    this.hoverOut = el('p', { class: 'occgrid-readout doorway-trap-hover', 'aria-live': 'polite' }, HOVER_HINT);
    this.flipText = el('p', { class: 'occgrid-readout doorway-trap-flip', 'aria-live': 'polite' });
    this.barBox = el('div', { class: 'doorway-trap-chart doorway-trap-bars', role: 'img', 'aria-label': 'Change of each beam’s log likelihood for the latest flip: no flip yet.' });
    this.curveBox = el('div', { class: 'doorway-trap-chart doorway-trap-curve', role: 'img', 'aria-label': 'Objective J(m) over flips: no flip yet.' });
    this.loop = frameLoop(this, (dt) => this.tick(dt));

    this.append(
      el('div', { class: 'doorway-trap-panes' }, this.panes.sweep.root, this.panes.map.root),
      this.hoverOut,
      this.flipText,
      el('div', { class: 'doorway-trap-charts' }, this.barBox, this.curveBox),
      el('p', { class: 'occgrid-caption' },
        'Orange outlines are the true walls; green wedges are sonar cones out to their readings. ',
        'The swept grid paints a cone’s whole arc at its reading: a cone that clips a door jamb reads the jamb’s range, so its arc crosses the doorway, and a one-cell wall closes the door. ',
        'The MAP climb asks instead which single binary map makes all readings most probable under the forward model: one occupied jamb cell explains a clipped cone, ',
        'and an occupied doorway cell would contradict the cone that reads the far wall straight through the door. ',
        'A red square is a cell the climb set occupied, a purple one a cell it cleared again; the yellow square is the latest flip, with the beams it changed (green raised, red dashed lowered).'),
      this.buildTwoCell(),
      copyLinkControl(this, DoorwayTrapElement.attributeSpec, () => this.linkState()),
    );

    this.bars = barChart(this.barBox, { title: 'Δ log p(z | x, m) per beam (stop.sonar), nats', yLabel: 'Δ nats', height: 170 });
    // Bars are read against zero: keep 0 inside the y range (raised beams
    // above, lowered ones below), whatever the data's own extent.
    this.bars.plot.scales.y.range = (u, min, max) => {
      const lo = Math.min(0, min ?? 0);
      const hi = Math.max(0, max ?? 0);
      const pad = (hi - lo) * 0.08 || 1;
      return [lo < 0 ? lo - pad : 0, hi > 0 ? hi + pad : 0];
    };
    this.curve = lineChart(this.curveBox, {
      title: 'Objective J(m) over flips', xLabel: 'flip', yLabel: 'J, nats', height: 170,
      series: [{ label: 'J(m)', color: COLORS.series[0] }],
    });
    if ('ResizeObserver' in window) {
      this.resizer = new ResizeObserver(() => this.layout());
      this.resizer.observe(this.querySelector('.doorway-trap-panes'));
    }
  }

  buildTwoCell() {
    this.diagram = el('canvas', {
      class: 'doorway-trap-diagram', tabindex: '0', role: 'img',
      'aria-label': 'Sonar cone with cells A and B. Drag a cell, or use the arrow keys to move cell B (Space switches to cell A).',
    });
    this.diagramCtx = hiDpiCanvas(this.diagram, DIAGRAM_W, DIAGRAM_H);
    this.arrangementButtons = [
      ['side', 'Side by side'], ['collinear', 'Collinear'], ['apart', 'Apart'],
    ].map(([key, label]) => {
      const b = button(label, () => this.setArrangement(key), { name: `arrange-${key}`, pressed: false });
      b.dataset.arrangement = key;
      return b;
    });
    this.readingSlider = slider({
      label: 'Reading z', min: 0.1, max: 3.0, step: 0.01, value: this.values.reading,
      format: (v) => (v >= MAX_RANGE ? `${v.toFixed(2)} m (no echo)` : `${v.toFixed(2)} m`),
      onInput: (v) => { if (this.query) { this.query.readings = [v]; this.updateJoint(); } },
      name: 'reading',
    });
    this.priorSlider = slider({
      label: 'Prior p₀', min: 0.05, max: 0.95, step: 0.05, value: this.values.prior,
      format: (v) => v.toFixed(2),
      onInput: (v) => { if (this.query) { this.query.prior = v; this.updateJoint(); } },
      name: 'prior',
    });
    this.jointBody = el('tbody');
    this.readingSlider.root.dataset.controls = 'sliders';
    this.priorSlider.root.dataset.controls = 'sliders';
    this.jointTable = el('table', { class: 'occgrid-table doorway-trap-joint' },
      el('caption', {}, 'Exact joint posterior vs the factored map'),
      el('thead', {}, el('tr', {},
        el('th', { scope: 'col' }, '(m_A m_B)'),
        el('th', { scope: 'col', title: 'expected range of the cone in this configuration' }, 'z*, m'),
        el('th', { scope: 'col', title: 'forward model density of the reading' }, 'p(z | m)'),
        el('th', { scope: 'col' }, 'true p(m | z)'),
        el('th', { scope: 'col' }, 'factored p_A · p_B'))),
      this.jointBody);
    this.marginalsOut = el('p', { class: 'occgrid-readout doorway-trap-marginals' });
    this.trapOut = el('p', { class: 'occgrid-readout doorway-trap-verdict', 'aria-live': 'polite' });

    this.diagram.addEventListener('pointerdown', (ev) => this.dragStart(ev));
    this.diagram.addEventListener('pointermove', (ev) => this.dragMove(ev));
    this.diagram.addEventListener('pointerup', (ev) => this.dragEnd(ev));
    this.diagram.addEventListener('pointercancel', (ev) => this.dragEnd(ev));
    this.diagram.addEventListener('keydown', (ev) => this.nudge(ev));
    this.diagram.addEventListener('focus', () => this.query && this.drawDiagram());
    this.diagram.addEventListener('blur', () => this.query && this.drawDiagram());

    return el('section', { class: 'doorway-trap-two-cell', 'aria-label': 'Two cells, one cone' },
      el('h3', {}, 'Two cells, one cone'),
      el('div', { class: 'doorway-trap-two-cell-layout' },
        el('div', { class: 'doorway-trap-diagram-box' },
          this.diagram,
          el('div', { class: 'occgrid-buttons', role: 'group', 'aria-label': 'arrangement of the two cells', dataset: { controls: 'arrangements' } }, this.arrangementButtons),
          this.readingSlider.root, this.priorSlider.root),
        el('div', { class: 'doorway-trap-table-box' },
          // Scrolls sideways in a narrow column; focusable so the keyboard can scroll it.
          el('div', { class: 'occgrid-scroll', tabindex: 0, role: 'region', 'aria-label': 'Joint posterior table' }, this.jointTable),
          this.marginalsOut, this.trapOut,
          el('p', { class: 'occgrid-caption' },
            'Both cells start at the prior. One echo from inside the cone says that something in it is occupied, not which cell: ',
            'the exact posterior puts almost no mass on “both free”, while the factored map, which keeps only p_A and p_B, ',
            'multiplies them and finds “both free” many times too likely. Put B behind A and it hides; move it in front of the echo and it is simply free.'))));
  }

  // ---- Core state ----

  create() {
    this.pause('sweep');
    this.pause('map');
    const v = this.values;
    let lastScan = null;
    let lastFlip = null;
    try {
      let scene;
      if (v.scene || v.seed !== undefined) scene = { ...(v.scene ?? {}), ...(v.seed !== undefined ? { seed: v.seed } : {}) };
      const next = new this.core.DoorwayTrap(scene);
      // A link may open the sweep and the climb part-way through.
      for (let i = 0; i < v.scans; i++) {
        const s = next.sweepStep();
        if (!s) break;
        lastScan = s;
      }
      for (let i = 0; i < v.flips; i++) {
        const f = next.mapStep();
        if (!f) break;
        lastFlip = f;
      }
      this.trap?.free();
      this.trap = next;
      this.view = next.view();
      clearError(this);
    } catch (e) {
      showError(this, e);
      return;
    }
    this.lastFlip = lastFlip;
    this.lastScan = lastScan;
    this.cursor = null;
    for (const p of Object.values(this.panes)) p.cssW = 0;
    this.layout();
  }

  /** Sets up the two-cell table from the attributes. */
  initTwoCell() {
    const v = this.values;
    try {
      this.query = this.core.chapterTwoCellQuery();
    } catch (e) {
      showError(this, e);
      return;
    }
    this.query.readings = [v.reading];
    this.query.prior = v.prior;
    this.readingSlider.set(v.reading);
    this.priorSlider.set(v.prior);
    if (!v.cells) {
      this.setArrangement(v.arrangement);
      return;
    }
    // Cells placed where a preset puts them count as that preset.
    const presets = { side: this.query.cells, ...ARRANGEMENTS };
    const same = (a, b) => a.every((c, j) => Math.abs(c.range - b[j].range) < 1e-9 && Math.abs(c.bearing_deg - b[j].bearing_deg) < 1e-9);
    const preset = Object.keys(presets).find((k) => same(v.cells, presets[k]));
    if (preset) this.setArrangement(preset);
    else {
      this.query.cells = v.cells.map((c) => ({ ...c }));
      this.moveCell(1, this.query.cells[1].range, this.query.cells[1].bearing_deg);
    }
  }

  sweepStep() {
    if (!this.trap) return false;
    const s = this.trap.sweepStep();
    if (s) this.lastScan = s;
    return s !== null;
  }

  mapStep() {
    if (!this.trap) return false;
    const flip = this.trap.mapStep();
    if (flip) this.lastFlip = flip;
    return flip !== null;
  }

  // ---- Play ----

  toggle(which) {
    if (this.playing[which]) this.pause(which);
    else this.play(which);
  }

  play(which) {
    if (!this.trap || this.playing[which]) return;
    const r = this.trap.report();
    if (which === 'sweep' && r.scansDone >= r.scans) { this.trap.sweepReset(); this.lastScan = null; }
    if (which === 'map' && this.trap.mapState().converged) { this.trap.mapReset(); this.lastFlip = null; }
    this.playing[which] = true;
    const b = which === 'sweep' ? this.sweepPlay : this.mapPlay;
    showPlaying(b, true);
    b.setAttribute('aria-label', `Pause ${which === 'sweep' ? 'the sweep' : 'the MAP climb'}`);
    this.owed = this.owed || { sweep: 0, map: 0 };
    this.owed[which] = 1; // the first step at once
    // The loop gets frames only while the widget is on screen.
    this.loop.start();
  }

  pause(which) {
    if (!this.playing[which]) return;
    this.playing[which] = false;
    const b = which === 'sweep' ? this.sweepPlay : this.mapPlay;
    showPlaying(b, false);
    b.setAttribute('aria-label', `Play ${which === 'sweep' ? 'the sweep' : 'the MAP climb'}`);
    if (!this.playing.sweep && !this.playing.map) this.loop.stop();
  }

  /** One animation frame, `dtMs` after the previous one. */
  tick(dtMs) {
    const dt = dtMs / 1000;
    let changed = false;
    try {
      for (const [which, rate, step] of [['sweep', SCANS_PER_SECOND, () => this.sweepStep()], ['map', FLIPS_PER_SECOND, () => this.mapStep()]]) {
        if (!this.playing[which]) continue;
        this.owed[which] += dt * rate;
        if (this.owed[which] >= 1) {
          this.owed[which] = Math.min(this.owed[which] - 1, 1);
          changed = true;
          if (!step()) this.pause(which);
        }
      }
    } catch (e) {
      showError(this, e);
      this.pause('sweep');
      this.pause('map');
    }
    if (changed) this.draw();
    return this.playing.sweep || this.playing.map;
  }

  // ---- Drawing ----

  layout() {
    if (!this.trap) return;
    const { width: w, height: h } = this.view;
    const widest = this.values['map-width'];
    for (const p of Object.values(this.panes)) {
      const cssW = Math.max(120, Math.min(widest, Math.floor(p.root.clientWidth || 320)));
      if (p.cssW === cssW) continue;
      p.cssW = cssW;
      p.ctx = hiDpiCanvas(p.canvas, cssW, Math.round((cssW * h) / w));
    }
    this.draw();
  }

  draw() {
    if (!this.trap) return;
    let report, state;
    try {
      const { width: w, height: h } = this.view;
      report = this.trap.report();
      state = this.trap.mapState();
      const sweep = this.panes.sweep;
      const map = this.panes.map;
      if (sweep.ctx) {
        drawMap(sweep.canvas, this.memory, this.trap.sweepRender(), w, h);
        this.overlaySweep(sweep, report);
      }
      if (map.ctx) {
        drawMap(map.canvas, this.memory, this.trap.mapRender(), w, h);
        this.overlayMap(map, state);
      }
    } catch (e) {
      showError(this, e);
      this.pause('sweep');
      this.pause('map');
      return;
    }
    this.report = report;
    this.state = state;
    this.readouts(report, state);
  }

  readouts(r, st) {
    const sweep = this.panes.sweep;
    const scan = this.lastScan;
    sweep.status.textContent = r.scansDone === 0
      ? `No scan yet: ${r.scans} stops of ${this.view.beamsPerScan} sonars each.`
      : `Scan ${r.scansDone} of ${r.scans}` + (scan && scan.scan === r.scansDone ? ` · ${scan.cellsVisited} cells visited, ${scan.cellsUpdated} updated` : '') + '.';
    sweep.door.textContent = `Doorway cells with p > 0.5: ${r.sweepClosed} of ${r.doorCells}` + (r.sweepClosed === r.doorCells ? ' — the door is closed.' : '.');
    const map = this.panes.map;
    const flips = st.flips.length;
    map.status.textContent = `Flip ${flips} · J = ${fixed(st.objective, 3)} nats · ${st.occupied} cells occupied` +
      (st.converged ? ' · local maximum: no single flip helps.' : '.');
    map.door.textContent = `MAP cells in the doorway: ${r.mapInDoorway}; on the far wall behind it: ${r.mapOnFarWall}.`;
    sweep.canvas.setAttribute('aria-label',
      `Swept map (Table 9.1) after ${r.scansDone} of ${r.scans} scans: ${r.sweepClosed} of ${r.doorCells} doorway cells ` +
      `above p = 0.5${r.sweepClosed === r.doorCells ? ', the door is closed' : ''}. Gray unknown, white free, black occupied; ` +
      `orange outlines the true walls. ${MAP_HINT}`);
    map.canvas.setAttribute('aria-label',
      `MAP map (Table 9.3) after ${flips} flip${flips === 1 ? '' : 's'}: ${st.occupied} cells occupied, ${r.mapInDoorway} in the doorway, ` +
      `${r.mapOnFarWall} on the far wall behind it; J = ${fixed(st.objective, 3)} nats${st.converged ? ', a local maximum' : ''}. ` +
      `White free, black occupied; orange outlines the true walls. ${MAP_HINT}`);

    Object.assign(this.dataset, {
      scan: String(r.scansDone), sweepClosed: String(r.sweepClosed), doorCells: String(r.doorCells),
      flips: String(flips), objective: String(st.objective), converged: String(st.converged),
      mapInDoorway: String(r.mapInDoorway), mapOnFarWall: String(r.mapOnFarWall),
    });

    // The current flip: its text, its per-beam bars.
    const f = flips ? st.flips[flips - 1] : null;
    if (f) {
      const up = f.beams.filter((b) => b.delta > 0).length;
      const down = f.beams.length - up;
      this.flipText.textContent = `Flip ${f.number}: cell (${f.ix}, ${f.iy}) ${f.toOccupied ? 'set occupied' : 'cleared'}, ` +
        `gain ${f.gain >= 0 ? '+' : ''}${fixed(f.gain, 3)} nats — ${up} beam${up === 1 ? '' : 's'} raised, ${down} lowered` +
        (f.priorTerm !== 0 ? `, prior ${f.priorTerm >= 0 ? '+' : ''}${fixed(f.priorTerm, 3)}` : '') + '.';
    } else {
      this.flipText.textContent = st.converged ? 'The climb ended at the all-free start.' : 'No flip yet: the climb starts from the all-free map.';
    }
    const labels = [];
    const values = [];
    if (f) {
      for (const b of f.beams) {
        const beam = this.view.beams[b.beam];
        labels.push(`${beam.scan + 1}.${beam.sonar + 1}`);
        values.push(b.delta);
      }
      if (f.priorTerm !== 0) { labels.push('prior'); values.push(f.priorTerm); }
    }
    this.bars.setData(labels, values);
    this.barBox.setAttribute('aria-label', f
      ? `Change of each beam’s log likelihood for flip ${f.number}, nats: ` + labels.map((l, i) => `${l === 'prior' ? 'prior' : `beam ${l}`} ${values[i] >= 0 ? '+' : ''}${fixed(values[i], 3)}`).join(', ') + '.'
      : 'Change of each beam’s log likelihood for the latest flip: no flip yet.');
    Object.assign(this.barBox.dataset, { flip: String(f ? f.number : 0), bars: String(values.length), values: JSON.stringify(values) });
    const xs = st.history.map((_, i) => i);
    this.curve.setData(xs, st.history);
    this.curveBox.setAttribute('aria-label', flips
      ? `Objective J(m) over ${flips} flip${flips === 1 ? '' : 's'}: from ${fixed(st.history[0], 3)} to ${fixed(st.history[st.history.length - 1], 3)} nats.`
      : `Objective J(m) over flips: no flip yet; J = ${fixed(st.objective, 3)} nats at the all-free start.`);
    Object.assign(this.curveBox.dataset, { points: String(st.history.length), last: String(st.history[st.history.length - 1]) });
  }

  /** Pixel helpers for a pane: grid cells (u east, v north) to CSS pixels. */
  frameOf(p) {
    const s = p.cssW / this.view.width;
    const h = this.view.height;
    return { s, X: (u) => u * s, Y: (v) => (h - v) * s };
  }

  drawTruth(ctx, { s, X, Y }) {
    ctx.save();
    ctx.strokeStyle = TRUTH_COLOR;
    ctx.lineWidth = 1.25;
    for (const [u0, v0, u1, v1] of this.view.walls) ctx.strokeRect(X(u0), Y(v1), (u1 - u0) * s, (v1 - v0) * s);
    const [du0, dv0, du1] = this.view.door;
    ctx.font = '600 11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    // Below the gap, in the room, where the flips on the wall line stay visible.
    const tx = X((du0 + du1) / 2);
    const ty = Y(dv0) + 3;
    const tw = ctx.measureText('door').width;
    ctx.fillStyle = 'rgba(255,255,255,0.8)';
    ctx.fillRect(tx - tw / 2 - 2, ty - 1, tw + 4, 13);
    ctx.fillStyle = TRUTH_COLOR;
    ctx.fillText('door', tx, ty);
    ctx.restore();
  }

  drawCone(ctx, { s, X, Y }, beam, color, { dashed = false, fill = true } = {}) {
    const hw = this.view.halfWidth;
    const r = beam.range * s;
    const a0 = -beam.angle - hw;
    const a1 = -beam.angle + hw;
    ctx.save();
    if (dashed) ctx.setLineDash([4, 3]);
    ctx.strokeStyle = color;
    ctx.lineWidth = 1.25;
    ctx.beginPath();
    ctx.moveTo(X(beam.u), Y(beam.v));
    ctx.arc(X(beam.u), Y(beam.v), r, a0, a1);
    ctx.closePath();
    if (fill) {
      ctx.fillStyle = color + '26';
      ctx.fill();
    }
    ctx.stroke();
    ctx.restore();
  }

  drawPoses(ctx, { X, Y }, highlight) {
    const per = this.view.beamsPerScan;
    ctx.save();
    for (let k = 0; k * per < this.view.beams.length; k++) {
      const b = this.view.beams[k * per];
      ctx.fillStyle = k === highlight ? POSE_COLOR : POSE_COLOR + '70';
      ctx.beginPath();
      ctx.arc(X(b.u), Y(b.v), k === highlight ? 4 : 2.5, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.restore();
  }

  overlaySweep(p, r) {
    const ctx = p.ctx;
    const fr = this.frameOf(p);
    this.drawTruth(ctx, fr);
    const current = r.scansDone - 1;
    if (current >= 0) {
      for (const b of this.view.beams) if (b.scan === current) this.drawCone(ctx, fr, b, COLORS.evidence);
    }
    this.drawPoses(ctx, fr, current);
    this.drawCursor(p, fr);
  }

  /** The keyboard cursor's cell, outlined in blue. */
  drawCursor(p, { s, X, Y }) {
    const c = this.cursor;
    if (!c || c.key !== p.key) return;
    const ctx = p.ctx;
    ctx.save();
    ctx.strokeStyle = COLORS.l0;
    ctx.lineWidth = 2;
    ctx.strokeRect(X(c.ix), Y(c.iy + 1), s, s);
    ctx.restore();
  }

  overlayMap(p, st) {
    const ctx = p.ctx;
    const fr = this.frameOf(p);
    const { s, X, Y } = fr;
    this.drawTruth(ctx, fr);
    this.drawPoses(ctx, fr, -1);
    const flips = st.flips;
    const current = flips.length ? flips[flips.length - 1] : null;
    if (current) {
      for (const c of current.beams) {
        const beam = this.view.beams[c.beam];
        if (c.delta > 0) this.drawCone(ctx, fr, beam, COLORS.evidence);
        else this.drawCone(ctx, fr, beam, LOWERED_COLOR, { dashed: true, fill: false });
      }
    }
    // Every flipped cell: its last state decides the mark.
    const lastOf = new Map();
    for (const f of flips) lastOf.set(f.cell, f);
    ctx.save();
    ctx.lineWidth = 1.5;
    for (const f of lastOf.values()) {
      ctx.strokeStyle = f.toOccupied ? SET_COLOR : CLEARED_COLOR;
      if (!f.toOccupied) ctx.setLineDash([2, 2]);
      ctx.strokeRect(X(f.ix) + 0.75, Y(f.iy + 1) + 0.75, s - 1.5, s - 1.5);
      ctx.setLineDash([]);
    }
    if (current) {
      const x = X(current.ix);
      const y = Y(current.iy + 1);
      ctx.strokeStyle = CURRENT_COLOR;
      ctx.lineWidth = 3;
      ctx.strokeRect(x - 1.5, y - 1.5, s + 3, s + 3);
      const label = `#${current.number}`;
      ctx.font = '700 12px system-ui, sans-serif';
      const tw = ctx.measureText(label).width;
      const lx = Math.min(x + s + 4, p.cssW - tw - 4);
      const ly = Math.max(y - 4, 14);
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(lx - 2, ly - 12, tw + 4, 15);
      ctx.fillStyle = '#1b1b1b';
      ctx.textBaseline = 'alphabetic';
      ctx.fillText(label, lx, ly);
    }
    ctx.restore();
    this.drawCursor(p, fr);
  }

  hover(key, ev) {
    if (!this.trap || !ev) {
      this.hoverOut.textContent = HOVER_HINT;
      return;
    }
    const p = this.panes[key];
    const rect = p.canvas.getBoundingClientRect();
    const s = rect.width / this.view.width;
    const ix = Math.floor((ev.clientX - rect.left) / s);
    const iy = this.view.height - 1 - Math.floor((ev.clientY - rect.top) / s);
    this.readCell(ix, iy);
  }

  /** Arrow keys move the cursor cell on a focused map. */
  keyCursor(key, ev) {
    const moves = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
    const m = moves[ev.key];
    if (!m || !this.trap) return;
    ev.preventDefault();
    this.moveCursor(key, m[0], m[1]);
  }

  /** Moves (or places, at the doorway) the cursor on map `key` and reads its cell. */
  moveCursor(key, dx, dy) {
    if (!this.trap) return;
    const { width: w, height: h, door } = this.view;
    const c = this.cursor && this.cursor.key === key ? this.cursor
      : { key, ix: Math.floor((door[0] + door[2]) / 2), iy: Math.floor(door[1]) };
    const ix = Math.max(0, Math.min(w - 1, c.ix + dx));
    const iy = Math.max(0, Math.min(h - 1, c.iy + dy));
    this.cursor = { key, ix, iy };
    this.draw();
    this.readCell(ix, iy);
  }

  /** Reads cell (ix, iy) of both halves into the readout line. */
  readCell(ix, iy) {
    if (ix < 0 || iy < 0 || ix >= this.view.width || iy >= this.view.height) return;
    try {
      const c = this.trap.cellInfo(ix, iy);
      this.hoverOut.textContent = `Cell (${c.ix}, ${c.iy}) · swept: l = ${fixed(c.l, 3)}, p = ${fixed(c.p, 3)}, ${c.updates} update${c.updates === 1 ? '' : 's'} · ` +
        `MAP: ${c.occupied ? 'occupied' : 'free'}, inside ${c.beams} cone${c.beams === 1 ? '' : 's'}, ` +
        `flipping it would change J by ${c.sensitivity >= 0 ? '+' : ''}${fixed(c.sensitivity, 3)} nats.`;
    } catch (e) {
      showError(this, e);
    }
  }

  async exportMap(key) {
    if (!this.trap) return;
    try {
      await downloadMapPair(`doorway-${key}`, this.trap.exportMap(key));
    } catch (e) {
      showError(this, e);
    }
  }

  // ---- The two-cell table ----

  setArrangement(key) {
    if (!this.core) return;
    let cells;
    try {
      cells = key === 'side' ? this.core.chapterTwoCellQuery().cells : ARRANGEMENTS[key];
      if (!this.query) this.query = this.core.chapterTwoCellQuery();
    } catch (e) {
      showError(this, e);
      return;
    }
    this.query.cells = cells.map((c) => ({ ...c }));
    this.arrangement = key;
    for (const b of this.arrangementButtons) b.setAttribute('aria-pressed', String(b.dataset.arrangement === key));
    this.updateJoint();
  }

  updateJoint() {
    let r;
    try {
      r = this.core.jointPosterior(this.query);
      clearError(this);
    } catch (e) {
      showError(this, e);
      return;
    }
    this.jointReport = r;
    const cell = (x, d = 4) => el('td', { dataset: { value: String(x) } }, fixed(x, d));
    this.jointBody.replaceChildren(...r.table.map((row) => el('tr', { dataset: { config: String(row.index) } },
      el('th', { scope: 'row' }, bits(row.occupied)),
      cell(row.expectedRange, 2), cell(row.likelihood, 4), cell(row.joint), cell(row.factored))));
    const [pa, pb] = r.marginals;
    this.marginalsOut.replaceChildren(
      'Marginals: p_A = ', el('output', { class: 'doorway-trap-pa', dataset: { value: String(pa) } }, fixed(pa, 4)),
      ', p_B = ', el('output', { class: 'doorway-trap-pb', dataset: { value: String(pb) } }, fixed(pb, 4)),
      ` · shared information ${fixed(r.mutualInformationBits, 3)} bits.`);
    this.trapOut.replaceChildren(
      '“Both free”: truly ', el('strong', { class: 'doorway-trap-free-true', dataset: { value: String(r.allFreeTrue) } }, fixed(r.allFreeTrue, 4)),
      ', factored ', el('strong', { class: 'doorway-trap-free-factored', dataset: { value: String(r.allFreeFactored) } }, fixed(r.allFreeFactored, 4)),
      ' — ', el('strong', { class: 'doorway-trap-ratio', dataset: { value: String(r.allFreeRatio) } }, `${fixed(r.allFreeRatio, r.allFreeRatio >= 10 ? 1 : 2)}×`),
      r.allFreeRatio >= 1 ? ' too likely under the product of marginals.' : ' as likely under the product of marginals.');
    this.drawDiagram();
  }

  /** Diagram geometry: the sensor at the left, the cone's axis pointing right. */
  diagramFrame() {
    const W = DIAGRAM_W;
    const H = DIAGRAM_H;
    const ox = 16;
    const oy = H / 2 - 8;
    const scale = (W - ox - 64) / DIAGRAM_RANGE;
    const toXY = (range, bearingDeg) => {
      const b = (bearingDeg * Math.PI) / 180;
      return [ox + range * Math.cos(b) * scale, oy - range * Math.sin(b) * scale];
    };
    return { W, H, scale, ox, oy, toXY };
  }

  drawDiagram() {
    const ctx = this.diagramCtx;
    const { W, H, scale, ox, oy, toXY } = this.diagramFrame();
    const q = this.query;
    const half = (q.beta_deg / 2) * (Math.PI / 180);
    const zMax = (q.model && q.model.z_max) || MAX_RANGE;
    const z = q.readings[0];
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, W, H);
    ctx.save();
    // The cone out to z_max, with metre ticks along its lower edge.
    ctx.fillStyle = COLORS.evidence + '1f';
    ctx.strokeStyle = COLORS.evidence;
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(ox, oy);
    ctx.arc(ox, oy, zMax * scale, -half, half);
    ctx.closePath();
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = '#4a4a44';
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    for (let m = 1; m <= Math.floor(zMax); m++) {
      const [x, y] = toXY(m, -q.beta_deg / 2);
      ctx.fillText(`${m} m`, x, y + 4);
    }
    // The reading: an arc across the cone (at z_max: no echo).
    ctx.strokeStyle = COLORS.evidence;
    ctx.lineWidth = 3;
    ctx.beginPath();
    ctx.arc(ox, oy, Math.min(z, zMax) * scale, -half, half);
    ctx.stroke();
    ctx.fillStyle = COLORS.evidence;
    ctx.font = '600 12px system-ui, sans-serif';
    ctx.textBaseline = 'bottom';
    const [zx, zy] = toXY(Math.min(z, zMax), q.beta_deg / 2);
    ctx.fillText(z >= zMax ? `z = ${z.toFixed(2)} m, no echo` : `z = ${z.toFixed(2)} m`, zx, zy - 4);
    // The cells (points of the query), labelled, shaded by their marginal.
    q.cells.forEach((c, j) => {
      const [x, y] = toXY(c.range, c.bearing_deg);
      const p = this.jointReport ? this.jointReport.marginals[j] : 0.5;
      const g = Math.round(255 * (1 - p));
      const color = j === 0 ? COLORS.series[1] : COLORS.l0;
      ctx.beginPath();
      ctx.arc(x, y, 7, 0, 2 * Math.PI);
      ctx.fillStyle = `rgb(${g},${g},${g})`;
      ctx.fill();
      ctx.lineWidth = 2.5;
      ctx.strokeStyle = color;
      ctx.stroke();
      if (j === this.movingCell && document.activeElement === this.diagram) {
        // The cell the arrow keys move.
        ctx.save();
        ctx.setLineDash([3, 2]);
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.arc(x, y, 11, 0, 2 * Math.PI);
        ctx.stroke();
        ctx.restore();
      }
      const label = j === 0 ? 'A' : 'B';
      ctx.font = '700 13px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.textBaseline = 'middle';
      const ly = c.bearing_deg > 0 || (c.bearing_deg === 0 && j === 1) ? y - 16 : y + 17;
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(x - 7, ly - 8, 14, 16);
      ctx.fillStyle = color;
      ctx.fillText(label, x, ly);
    });
    ctx.fillStyle = POSE_COLOR;
    ctx.beginPath();
    ctx.arc(ox, oy, 4, 0, 2 * Math.PI);
    ctx.fill();
    ctx.restore();
    this.diagram.setAttribute('aria-label',
      `Sonar cone with cell A at ${q.cells[0].range.toFixed(2)} m, ${q.cells[0].bearing_deg.toFixed(1)}° and cell B at ` +
      `${q.cells[1].range.toFixed(2)} m, ${q.cells[1].bearing_deg.toFixed(1)}°; reading ${z.toFixed(2)} m. ` +
      `Drag a cell, or use the arrow keys to move cell ${this.movingCell === 0 ? 'A' : 'B'} (left and right in range, up and down in bearing); ` +
      `Space switches to cell ${this.movingCell === 0 ? 'B' : 'A'}.`);
  }

  /** A pointer position on the diagram as (range, bearing) inside the cone. */
  pointerToCell(ev) {
    const rect = this.diagram.getBoundingClientRect();
    const { W, scale, ox, oy } = this.diagramFrame();
    const k = W / rect.width;
    const x = (ev.clientX - rect.left) * k;
    const y = (ev.clientY - rect.top) * k;
    const fwd = (x - ox) / scale;
    const left = (oy - y) / scale;
    const half = this.query.beta_deg / 2;
    const range = Math.min(MAX_RANGE, Math.max(MIN_RANGE, Math.hypot(fwd, left)));
    const bearing = Math.max(-half, Math.min(half, (Math.atan2(left, fwd) * 180) / Math.PI));
    return { x, y, range: Math.round(range * 100) / 100, bearing_deg: Math.round(bearing * 10) / 10 };
  }

  dragStart(ev) {
    if (!this.query) return;
    const { toXY } = this.diagramFrame();
    const at = this.pointerToCell(ev);
    let best = -1;
    let bestD = 18;
    this.query.cells.forEach((c, j) => {
      const [x, y] = toXY(c.range, c.bearing_deg);
      const d = Math.hypot(x - at.x, y - at.y);
      if (d < bestD) { bestD = d; best = j; }
    });
    if (best < 0) return;
    this.dragging = best;
    this.diagram.setPointerCapture(ev.pointerId);
    ev.preventDefault();
  }

  dragMove(ev) {
    if (this.dragging === undefined || this.dragging < 0) return;
    const { range, bearing_deg } = this.pointerToCell(ev);
    this.moveCell(this.dragging, range, bearing_deg);
  }

  dragEnd(ev) {
    if (this.dragging === undefined) return;
    this.dragging = undefined;
    if (this.diagram.hasPointerCapture(ev.pointerId)) this.diagram.releasePointerCapture(ev.pointerId);
  }

  /**
   * Arrow keys move a cell (B unless Space or Enter switched to A): right
   * and left in range (5 cm), up and down in bearing (1°).
   */
  nudge(ev) {
    if (!this.query) return;
    if (ev.key === ' ' || ev.key === 'Enter') {
      ev.preventDefault();
      this.movingCell = 1 - this.movingCell;
      this.drawDiagram();
      return;
    }
    const j = this.movingCell;
    const b = this.query.cells[j];
    const half = this.query.beta_deg / 2;
    const moves = {
      ArrowRight: [0.05, 0], ArrowLeft: [-0.05, 0], ArrowUp: [0, 1], ArrowDown: [0, -1],
    };
    const m = moves[ev.key];
    if (!m) return;
    ev.preventDefault();
    const range = Math.min(MAX_RANGE, Math.max(MIN_RANGE, Math.round((b.range + m[0]) * 100) / 100));
    const bearing = Math.max(-half, Math.min(half, Math.round((b.bearing_deg + m[1]) * 10) / 10));
    this.moveCell(j, range, bearing);
  }

  moveCell(j, range, bearingDeg) {
    this.query.cells[j] = { range, bearing_deg: bearingDeg };
    this.arrangement = 'custom';
    for (const b of this.arrangementButtons) b.setAttribute('aria-pressed', 'false');
    this.updateJoint();
  }
}

if (!customElements.get('occgrid-doorway-trap')) customElements.define('occgrid-doorway-trap', DoorwayTrapElement);

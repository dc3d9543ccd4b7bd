// <occgrid-doorway-trap>: why a wide sonar cone closes an open door in an
// occupancy grid, and how MAP mapping keeps it open (Probabilistic Robotics
// Tables 9.1–9.3; Table 9.3; docs/ARCHITECTURE.md, "The independence trap" and "Sessions and panes").
//
// Left, Table 9.1 swept literally over every cell with a 22° sonar and the
// inverse model of Table 9.2, one stop's scan at a time: a cone that
// straddles a door jamb paints its whole arc occupied, across the doorway.
// Right, the MAP hill climb of Table 9.3 on the same readings, one flip at a
// time: each flipped cell is marked, a bar chart shows how the flip changed
// each beam's log likelihood, and a curve shows the objective over flips.
// Before the first scan and the first flip, both panes draw every reading's
// cone with an arc at its reading, so that a reader can predict where the
// climb begins. Cells no reading reached are undecided in the MAP map (gray,
// exported unknown), and the hover says so.
// Below, the two-cell table (widgets/lib/two-cell-table.js): the exact joint
// posterior of two cells in one cone against the product of their
// marginals. Every number comes from the wasm core; this module draws, lays
// out and forwards input.
//
// Attributes (see `attributeSpec` below and the README's "Embedding"):
// seed, scene, autoplay, scans, flips, arrangement, cells, reading, prior,
// map-width, controls.
import { startWidget } from './lib/start.js';
import { workBudget, workInSlices } from './lib/work-budget.js';
import { COLORS, barChart, lineChart } from './lib/chart.js';
import {
  el, button, showError, clearError,
  frameLoop, prefersReducedMotion, fixed, grouped, pacer, showPlaying, startTurn,
} from './lib/ui.js';
import {
  ANY_NUMBER, applyControls, controlGroups, flag, formatControls, jsonObject, oneOf, steps, whole,
} from './lib/attributes.js';
import { copyLinkControl } from './lib/state.js';
import { arrowCell, exportButton, exportMap, followResize, pointerCell, resetPaneSizes, sizePanes } from './lib/pane.js';
import { floatingReadout, followCellPointer, mapStage, placeReadout } from './lib/cell-pointer.js';
import { drawCones, drawDots, drawMapImage, layerStack, outlineBox, outlineCell } from './lib/layers.js';
import { TwoCellTable, cellsType } from './lib/two-cell-table.js';

/** Sweep scans and MAP flips per second while playing. */
/**
 * The MAP search is set up in calls of about this many ms (a fine scene's
 * incidence and gains are a long task in one call), the first of this many
 * units (raster steps), which its time corrects.
 */
const SETUP_SLICE_MS = 12;
const FIRST_SETUP_UNITS = 50_000;
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

const GROUPS = ['playback', 'arrangements', 'sliders', 'export', 'link'];
/** The attributes of the two-cell table. */
const TWO_CELL_KEYS = ['arrangement', 'cells', 'reading', 'prior'];
const HOVER_HINT = 'Point at a cell (or focus a map and use the arrow keys) to read it.';
/** What the MAP map says of a cell (the core's `map` of a cell readout). */
const MAP_CELL_TEXT = { occupied: 'occupied', free: 'free', undecided: 'undecided (no reading reached it)' };
/** Every reading's cone before the first step: faint, with a firm arc at the reading. */
const ALL_CONES = { color: COLORS.evidence, fillAlpha: '09', outline: 'arc', lineWidth: 1.25 };
const MAP_HINT = 'Arrow keys move a cursor cell whose values are read out below the maps.';

class DoorwayTrapElement extends HTMLElement {
  static attributeSpec = {
    seed: { type: whole(0, Number.MAX_SAFE_INTEGER), doc: 'seed of the sonar readings’ noise; absent: the chapter’s' },
    scene: { type: jsonObject('{"prior": 0.3}'), doc: 'fields of the doorway scene to override (the core checks each); absent: the chapter’s room and door' },
    autoplay: { type: flag(), default: 'on', doc: 'play both halves when first scrolled into view (never under prefers-reduced-motion)' },
    // The most scans, the table's ranges and the cone's reach and
    // half-width are the core's (`constants().limits` and
    // `constants().twoCellTable`), taken once it has loaded.
    scans: {
      type: whole(0, Number.MAX_SAFE_INTEGER), default: '0', doc: 'sweep scans done before the first frame',
      core: (k) => ({ type: whole(0, k.limits.doorwayTrap.maxScans) }),
    },
    flips: { type: whole(0, 100_000), default: '0', doc: 'MAP flips done before the first frame (the climb stops at its local maximum)' },
    arrangement: { type: oneOf(['side', 'collinear', 'apart']), default: 'side', doc: 'the two cells of the two-cell table: side by side, one behind the other, or apart' },
    cells: {
      type: cellsType({ minRange: 0, maxRange: Infinity, halfConeDeg: 180 }), doc: 'the two cells placed by hand, "rangeA, bearingA, rangeB, bearingB" (metres, degrees); overrides arrangement',
      core: (k) => ({ type: cellsType({ minRange: k.limits.twoCellTable.reading.min, ...k.twoCellTable }) }),
    },
    reading: {
      type: ANY_NUMBER, default: '2.00', doc: 'the two-cell table’s reading z, metres (at the sonar’s z_max: no echo)',
      core: (k) => ({ type: steps(k.limits.twoCellTable.reading, 'm') }),
    },
    prior: { type: ANY_NUMBER, default: '0.50', doc: 'the two-cell table’s prior occupancy p₀', core: (k) => ({ type: steps(k.limits.twoCellTable.prior) }) },
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
    this.cursor = null; // { key, col, row }: the keyboard cursor on a map, image units
    // One step at most per frame, the first at once (see `play`).
    this.pace = { sweep: pacer(SCANS_PER_SECOND, 1), map: pacer(FLIPS_PER_SECOND, 1) };
  }

  connectedCallback() {
    // The runs are made when the widget first nears the screen: a reader
    // opening the chapter waits for no widget further down.
    return startWidget(this, DoorwayTrapElement.attributeSpec, {
      build: () => {
        this.values = this.attrs.read();
        this.build();
        applyControls(this, this.values.controls);
      },
      // The two cells and the reading checked against the core's cone.
      withCore: (constants) => { this.values = this.attrs.resolve(constants); },
      whenSeen: async () => {
        this.started = true;
        await this.create();
        if (this.values.autoplay && !prefersReducedMotion() && this.trap) {
          this.play('sweep');
          this.play('map');
        }
        // The two-cell table in a turn of its own: with the scene's run and
        // first drawing, one task would hold both halves' work.
        await startTurn();
        this.twoCell.start(this.core, this.values);
      },
      ahead: true,
      // A link about the two cells (exercises 2 and 3) lands on their table.
      landing: (keys) => (TWO_CELL_KEYS.some((k) => keys.has(k)) ? this.twoCell.root : null),
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
      resetPaneSizes(Object.values(this.panes));
      this.layout();
    } else if (!this.core || !this.started) return;
    else if (['seed', 'scene', 'scans', 'flips'].includes(name)) this.create();
    else if (TWO_CELL_KEYS.includes(name)) this.twoCell.start(this.core, this.values);
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    const v = this.values;
    return {
      seed: v.seed, scene: v.scene ? JSON.stringify(v.scene) : null,
      autoplay: this.playing.sweep || this.playing.map ? 'on' : 'off',
      scans: this.report ? this.report.scansDone : v.scans,
      flips: this.state ? this.state.flips.length : v.flips,
      ...this.twoCell.linkState(),
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
      // The tapped or pointed cell's values float over its map (on a phone
      // the line below both maps is a screen away).
      const stage = mapStage(canvas);
      const status = el('p', { class: 'occgrid-readout doorway-trap-status', 'aria-live': 'polite' }, 'Loading…');
      const door = el('p', { class: 'occgrid-readout doorway-trap-door' });
      const save = exportButton({
        name: `export-${key}`, title: `${exportLabel} as a ROS map_server PGM + YAML pair`,
        spoken: exportLabel.replace(/^Export the /, ''), onClick: () => this.exportMap(key),
      });
      const root = el('figure', { class: `doorway-trap-pane doorway-trap-${key}`, dataset: { map: key } },
        el('figcaption', {}, el('strong', {}, title), ' ', el('span', { class: 'doorway-trap-note' }, note)),
        el('div', { class: 'occgrid-controls doorway-trap-buttons', dataset: { controls: 'playback' } }, controls),
        stage, status, door,
        el('div', { class: 'doorway-trap-foot', dataset: { controls: 'export' } }, save));
      followCellPointer(canvas, {
        point: (ev) => this.hover(key, ev),
        leave: () => this.hover(key, null),
        keyboardFocus: () => {
          if (this.trap && (!this.cursor || this.cursor.key !== key)) this.placeCursor(key, this.cursorOn(key));
        },
      });
      canvas.addEventListener('keydown', (ev) => this.keyCursor(key, ev));
      canvas.addEventListener('blur', () => {
        this.cursor = null;
        this.draw();
      });
      return { key, canvas, stage, status, door, root, layers: key === 'sweep' ? this.sweepLayers() : this.mapLayers() };
    };

    this.sweepPlay = button('Play', () => this.toggle('sweep'), { name: 'sweep-play', pressed: false });
    this.mapPlay = button('Play', () => this.toggle('map'), { name: 'map-play', pressed: false });
    const sweepStep = button('Next scan', () => { this.pause('sweep'); this.sweepStep(); this.draw(); }, { name: 'sweep-step' });
    const mapStep = button('Step', () => { this.pause('map'); this.mapStep(); this.draw(); }, { name: 'map-step' });
    for (const [b, what] of [[this.sweepPlay, 'the sweep'], [this.mapPlay, 'the MAP climb']]) b.setAttribute('aria-label', `Play ${what}`);
    mapStep.setAttribute('aria-label', 'Step the MAP climb by one flip');
    this.panes = {
      sweep: pane('sweep', 'Table 9.1, swept', '· every cell, the nearest cone, Table 9.2', 'Export the swept map', [
        sweepStep, this.sweepPlay,
        button('Reset sweep', () => { this.pause('sweep'); this.trap?.sweepReset(); this.lastScan = null; this.draw(); }, { name: 'sweep-reset', title: 'Back to the empty grid' }),
      ]),
      map: pane('map', 'MAP, hill climbing', '· Table 9.3, one flip at a time', 'Export the MAP map', [
        mapStep, this.mapPlay,
        button('Reset MAP', () => { this.pause('map'); this.trap?.mapReset(); this.lastFlip = null; this.draw(); }, { name: 'map-reset', title: 'Back to the all-free start' }),
      ]),
    };
    this.hoverOut = el('p', { class: 'occgrid-readout doorway-trap-hover', 'aria-live': 'polite' }, HOVER_HINT);
    this.hoverFloat = floatingReadout();
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
        'Orange outlines are the true walls; green wedges are sonar cones out to their readings (before the first step, every reading’s, with an arc at its range). ',
        'The swept grid paints a cone’s whole arc at its reading: a cone that clips a door jamb reads the jamb’s range, so its arc crosses the doorway, and a one-cell wall closes the door. ',
        'The MAP climb asks instead which single binary map makes all readings most probable under the forward model: one occupied jamb cell explains a clipped cone, ',
        'and an occupied doorway cell would contradict the cone that reads the far wall straight through the door. ',
        'The MAP map holds no uncertainty about the cells it decided: each is free or occupied, nothing in between; ',
        'gray cells are undecided: no reading reached them, so it decides nothing about them (its export marks them unknown). ',
        'J(m), the objective, is the log posterior of the binary map up to a constant: the sum over every reading of log p(z | x, m) under the forward model, plus l0 for each occupied cell (the prior of independent cells); each flip is the one that raises it most, and the bars show which readings its flip made more or less probable. ',
        'A red square is a cell the climb set occupied, a purple one a cell it cleared again; the yellow square is the latest flip, with the beams it changed (green raised, red dashed lowered).'),
      (this.twoCell = new TwoCellTable(this, this.values)).root,
      copyLinkControl(this, DoorwayTrapElement.attributeSpec, () => this.linkState()),
    );

    this.bars = barChart(this.barBox, {
      title: 'Δ log p(z | x, m) per beam, nats', yLabel: 'Δ nats', height: 170,
      // Bars are read against zero: keep 0 inside the y range (raised beams
      // above, lowered ones below), whatever the data's own extent.
      yRange: (u, min, max) => {
        const lo = Math.min(0, min ?? 0);
        const hi = Math.max(0, max ?? 0);
        const pad = (hi - lo) * 0.08 || 1;
        return [lo < 0 ? lo - pad : 0, hi > 0 ? hi + pad : 0];
      },
    });
    this.curve = lineChart(this.curveBox, {
      title: 'Objective J(m) over flips', xLabel: 'flip', yLabel: 'J, nats', height: 170, wholeX: true,
      series: [{ label: 'J(m)', color: COLORS.series[0] }],
    });
    this.resizer = followResize(this.querySelector('.doorway-trap-panes'), () => this.layout());
  }

  // ---- Core state ----

  async create() {
    this.pause('sweep');
    this.pause('map');
    // A later create() (an attribute changed meanwhile) supersedes this one.
    const generation = (this.generation = (this.generation ?? 0) + 1);
    const v = this.values;
    let lastScan = null;
    let lastFlip = null;
    let start = null;
    try {
      let scene;
      if (v.scene || v.seed !== undefined) scene = { ...(v.scene ?? {}), ...(v.seed !== undefined ? { seed: v.seed } : {}) };
      start = new this.core.DoorwayTrapStart(scene);
      // The budget learns per run: each starts from the first guess.
      const budget = workBudget(SETUP_SLICE_MS, FIRST_SETUP_UNITS);
      if (!(await workInSlices(start, budget, () => generation === this.generation))) return;
      const next = start.finish();
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
      this.unreached = next.unreachedCells();
      this.panes.sweep.root.querySelector('.doorway-trap-note').textContent =
        `· every cell, the nearest ${this.view.betaDeg}° cone, Table 9.2`;
      clearError(this);
    } catch (e) {
      showError(this, e);
      // With no scene there is nothing to wait for: say so where the
      // panes would say how far they have got.
      if (!this.trap) {
        for (const pane of Object.values(this.panes)) {
          pane.status.textContent = 'No map: the scene was refused (see the message above).';
          pane.door.textContent = '';
        }
        this.dataset.state = 'refused';
      }
      return;
    } finally {
      start?.free();
    }
    this.dataset.state = 'ready';
    this.lastFlip = lastFlip;
    this.lastScan = lastScan;
    this.cursor = null;
    resetPaneSizes(Object.values(this.panes));
    this.layout();
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
    this.pace[which].reset(1); // the first step at once
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
    let changed = false;
    try {
      for (const [which, step] of [['sweep', () => this.sweepStep()], ['map', () => this.mapStep()]]) {
        if (!this.playing[which] || this.pace[which].take(dtMs) === 0) continue;
        changed = true;
        if (!step()) this.pause(which);
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
    sizePanes(Object.values(this.panes), this.view.width, this.view.height, this.values['map-width'], 320);
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
        drawMapImage(sweep.canvas, this.memory, this.trap.sweepRender(), w, h);
        sweep.layers.draw({ ctx: sweep.ctx, s: sweep.cssW / w, pane: sweep, report });
      }
      if (map.ctx) {
        drawMapImage(map.canvas, this.memory, this.trap.mapRender(), w, h);
        map.layers.draw({ ctx: map.ctx, s: map.cssW / w, pane: map, state });
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
    const readings = this.view.beams.length;
    sweep.status.textContent = r.scansDone === 0
      ? `No scan yet: ${grouped(r.scans)} stops of ${grouped(this.view.beamsPerScan)} sonars each; all ${grouped(readings)} readings’ cones are drawn, each with an arc at its reading.`
      : `Scan ${grouped(r.scansDone)} of ${grouped(r.scans)}` + (scan && scan.scan === r.scansDone ? ` · ${grouped(scan.cellsVisited)} cells visited, ${grouped(scan.cellsUpdated)} updated` : '') + '.';
    sweep.door.textContent = `Doorway cells with p > 0.5: ${grouped(r.sweepClosed)} of ${grouped(r.doorCells)}` + (r.sweepClosed === r.doorCells ? ' — the door is closed.' : '.');
    const map = this.panes.map;
    const flips = st.flips.length;
    map.status.textContent = `Flip ${grouped(flips)} · J = ${fixed(st.objective, 3)} nats · ${grouped(st.occupied)} cells occupied` +
      (st.converged ? ' · local maximum: no single flip helps.' : '.') +
      (flips === 0 ? ` The ${grouped(readings)} readings’ cones are drawn, each with an arc at its reading.` : '');
    map.door.textContent = `MAP cells in the doorway: ${grouped(r.mapInDoorway)}; on the far wall behind it: ${grouped(r.mapOnFarWall)}.`;
    sweep.canvas.setAttribute('aria-label',
      `Swept map (Table 9.1) after ${grouped(r.scansDone)} of ${grouped(r.scans)} scans: ${grouped(r.sweepClosed)} of ${grouped(r.doorCells)} doorway cells ` +
      `above p = 0.5${r.sweepClosed === r.doorCells ? ', the door is closed' : ''}. Gray unknown, white free, black occupied; ` +
      `orange outlines the true walls. ${MAP_HINT}`);
    map.canvas.setAttribute('aria-label',
      `MAP map (Table 9.3) after ${grouped(flips)} flip${flips === 1 ? '' : 's'}: ${grouped(st.occupied)} cells occupied, ${grouped(r.mapInDoorway)} in the doorway, ` +
      `${grouped(r.mapOnFarWall)} on the far wall behind it; J = ${fixed(st.objective, 3)} nats${st.converged ? ', a local maximum' : ''}. ` +
      `White free, black occupied, gray the ${grouped(this.unreached)} undecided cells no reading reached; orange outlines the true walls. ${MAP_HINT}`);

    Object.assign(this.dataset, {
      unreached: String(this.unreached),
      scan: String(r.scansDone), sweepClosed: String(r.sweepClosed), doorCells: String(r.doorCells),
      flips: String(flips), objective: String(st.objective), converged: String(st.converged),
      mapInDoorway: String(r.mapInDoorway), mapOnFarWall: String(r.mapOnFarWall),
    });

    // The current flip: its text, its per-beam bars.
    const f = flips ? st.flips[flips - 1] : null;
    if (f) {
      const up = f.beams.filter((b) => b.delta > 0).length;
      const down = f.beams.length - up;
      this.flipText.textContent = `Flip ${grouped(f.number)}: cell (${f.ix}, ${f.iy}) ${f.toOccupied ? 'set occupied' : 'cleared'}, ` +
        `gain ${f.gain >= 0 ? '+' : ''}${fixed(f.gain, 3)} nats — ${up} beam${up === 1 ? '' : 's'} raised, ${down} lowered` +
        (f.priorTerm !== 0 ? `, prior ${f.priorTerm >= 0 ? '+' : ''}${fixed(f.priorTerm, 3)}` : '') + '.';
    } else {
      this.flipText.textContent = st.converged ? 'The climb ended at the all-free start.'
        : 'No flip yet: the climb starts from the all-free map. Which cell will it flip first? The cones above show every reading.';
    }
    const labels = [];
    const values = [];
    if (f) {
      for (const b of f.beams) {
        const beam = this.view.beams[b.beam];
        labels.push(`scan ${beam.scan + 1}\nbeam ${beam.sonar + 1}`);
        values.push(b.delta);
      }
      if (f.priorTerm !== 0) { labels.push('prior'); values.push(f.priorTerm); }
    }
    this.bars.setData(labels, values);
    this.barBox.setAttribute('aria-label', f
      ? `Change of each beam’s log likelihood for flip ${grouped(f.number)}, nats: ` + labels.map((l, i) => `${l.replace('\n', ', ')} ${values[i] >= 0 ? '+' : ''}${fixed(values[i], 3)}`).join(', ') + '.'
      : 'Change of each beam’s log likelihood for the latest flip: no flip yet.');
    Object.assign(this.barBox.dataset, { flip: String(f ? f.number : 0), bars: String(values.length), values: JSON.stringify(values) });
    const xs = st.history.map((_, i) => i);
    this.curve.setData(xs, st.history);
    this.curveBox.setAttribute('aria-label', flips
      ? `Objective J(m) over ${grouped(flips)} flip${flips === 1 ? '' : 's'}: from ${fixed(st.history[0], 3)} to ${fixed(st.history[st.history.length - 1], 3)} nats.`
      : `Objective J(m) over flips: no flip yet; J = ${fixed(st.objective, 3)} nats at the all-free start.`);
    Object.assign(this.curveBox.dataset, { points: String(st.history.length), last: String(st.history[st.history.length - 1]) });
  }

  /**
   * The swept pane's layers: the current scan's cones, the true walls over
   * them (so the door's label stays legible), the stops, the cursor.
   */
  sweepLayers() {
    const layers = layerStack();
    layers.add(({ ctx, s, report }) => {
      // Before the first scan, every reading's cone: what the sweep will paint.
      if (report.scansDone === 0) return drawCones(ctx, s, this.view.beams, ALL_CONES);
      const current = report.scansDone - 1;
      for (const b of this.view.beams) if (b.scan === current) drawCones(ctx, s, [b], { color: COLORS.evidence });
    });
    layers.add((f) => this.drawTruth(f));
    layers.add(({ ctx, s, report }) => this.drawPoses(ctx, s, report.scansDone - 1));
    layers.add((f) => this.drawCursor(f));
    return layers;
  }

  /**
   * The MAP pane's layers: the beams the latest flip changed (raised
   * filled, lowered dashed; before the first flip, every reading's cone),
   * the true walls over them, the stops, every flipped cell (set red,
   * cleared purple), the latest flip with its number, the cursor.
   */
  mapLayers() {
    const layers = layerStack();
    layers.add(({ ctx, s, state }) => {
      const current = state.flips.at(-1);
      // Before the first flip, every reading's cone with an arc at its
      // reading: the climb's first flips lie where the most arcs meet.
      if (!current) return drawCones(ctx, s, this.view.beams, ALL_CONES);
      for (const c of current.beams) {
        const beam = this.view.beams[c.beam];
        if (c.delta > 0) drawCones(ctx, s, [beam], { color: COLORS.evidence });
        else drawCones(ctx, s, [beam], { color: LOWERED_COLOR, dashed: true, fillAlpha: null });
      }
    });
    layers.add((f) => this.drawTruth(f));
    layers.add(({ ctx, s }) => this.drawPoses(ctx, s, -1));
    layers.add(({ ctx, s, state }) => {
      // Every flipped cell: its last state decides the mark.
      const lastOf = new Map();
      for (const f of state.flips) lastOf.set(f.cell, f);
      for (const f of lastOf.values()) {
        outlineCell(ctx, s, f, f.toOccupied
          ? { color: SET_COLOR, lineWidth: 1.5, pad: -0.75 }
          : { color: CLEARED_COLOR, lineWidth: 1.5, pad: -0.75, dash: [2, 2] });
      }
    });
    layers.add(({ ctx, s, pane, state }) => {
      const current = state.flips.at(-1);
      if (!current) return;
      const cell = current;
      outlineCell(ctx, s, cell, { color: CURRENT_COLOR, lineWidth: 3, pad: 1.5 });
      const x = cell.col * s;
      const y = cell.row * s;
      const label = `#${grouped(current.number)}`;
      ctx.save();
      ctx.font = '700 12px system-ui, sans-serif';
      const tw = ctx.measureText(label).width;
      const lx = Math.min(x + s + 4, pane.cssW - tw - 4);
      const ly = Math.max(y - 4, 14);
      ctx.fillStyle = 'rgba(255,255,255,0.85)';
      ctx.fillRect(lx - 2, ly - 12, tw + 4, 15);
      ctx.fillStyle = '#1b1b1b';
      ctx.textBaseline = 'alphabetic';
      ctx.fillText(label, lx, ly);
      ctx.restore();
    });
    layers.add((f) => this.drawCursor(f));
    return layers;
  }

  /** The true walls, outlined, and the door's label below the gap. */
  drawTruth({ ctx, s }) {
    for (const box of this.view.walls) outlineBox(ctx, s, box, { color: TRUTH_COLOR, lineWidth: 1.25 });
    ctx.save();
    ctx.font = '600 11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    // Below the gap, in the room, where the flips on the wall line stay visible.
    const tx = this.view.doorLabel.x * s;
    const ty = this.view.doorLabel.y * s + 3;
    const tw = ctx.measureText('door').width;
    ctx.fillStyle = 'rgba(255,255,255,0.8)';
    ctx.fillRect(tx - tw / 2 - 2, ty - 1, tw + 4, 13);
    ctx.fillStyle = TRUTH_COLOR;
    ctx.fillText('door', tx, ty);
    ctx.restore();
  }

  /** The robot's stops, the `highlight`-th larger and opaque. */
  drawPoses(ctx, s, highlight) {
    this.view.stops.forEach((stop, k) => drawDots(ctx, s, [stop], k === highlight
      ? { color: POSE_COLOR, radius: 4 }
      : { color: POSE_COLOR + '70', radius: 2.5 }));
  }

  /** The keyboard cursor's cell, outlined in blue. */
  drawCursor({ ctx, s, pane }) {
    const c = this.cursor;
    if (c && c.key === pane.key) outlineCell(ctx, s, c, { color: COLORS.l0, lineWidth: 2 });
  }

  hover(key, ev) {
    if (!this.trap || !ev) {
      this.hoverOut.textContent = HOVER_HINT;
      this.hoverFloat.hidden = true;
      return;
    }
    const { col, row } = pointerCell(this.panes[key].canvas, ev, this.view.width, this.view.height);
    this.readCell(col, row, key);
  }

  /** Arrow keys move the cursor cell on a focused map. */
  keyCursor(key, ev) {
    if (!this.trap) return;
    const to = arrowCell(ev, this.cursorOn(key), this.view.width, this.view.height);
    if (!to) return;
    ev.preventDefault();
    this.placeCursor(key, to);
  }

  /** The cursor on map `key`, or where it starts: the doorway. */
  cursorOn(key) {
    return this.cursor && this.cursor.key === key ? this.cursor : this.view.doorCell;
  }

  /** Puts the cursor on map `key` at `cell` (image units) and reads the cell. */
  placeCursor(key, { col, row }) {
    this.cursor = { key, col, row };
    this.draw();
    this.readCell(col, row, key);
  }

  /** Reads image cell (col, row) of both halves into the readout line, and over map `key`. */
  readCell(col, row, key) {
    if (col < 0 || row < 0 || col >= this.view.width || row >= this.view.height) return;
    try {
      const c = this.trap.cellInfo(col, row);
      this.hoverOut.textContent = `Cell (${c.ix}, ${c.iy}) · swept: l = ${fixed(c.l, 3)}, p = ${fixed(c.p, 3)}, ${grouped(c.updates)} update${c.updates === 1 ? '' : 's'} · ` +
        `MAP: ${MAP_CELL_TEXT[c.map]}, inside ${grouped(c.beams)} cone${c.beams === 1 ? '' : 's'}, ` +
        `flipping it would change J by ${c.sensitivity >= 0 ? '+' : ''}${fixed(c.sensitivity, 3)} nats.`;
      this.hoverOut.dataset.map = c.map;
      this.hoverFloat.textContent = this.hoverOut.textContent;
      placeReadout(this.hoverFloat, this.panes[key].stage, row, this.view.height);
    } catch (e) {
      showError(this, e);
    }
  }

  exportMap(key) {
    if (this.trap) return exportMap(this, `doorway-${key}`, () => this.trap.exportMap(key));
  }
}

if (!customElements.get('occgrid-doorway-trap')) customElements.define('occgrid-doorway-trap', DoorwayTrapElement);

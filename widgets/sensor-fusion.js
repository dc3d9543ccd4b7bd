// <occgrid-sensor-fusion>: two sensors, two questions, and the max rule
// (Probabilistic Robotics eq. 9.9; docs/ARCHITECTURE.md, "Two sensors" and "Sessions and panes").
//
// A robot drives a lap around a table. A sonar ring at table height sees
// the top; a LiDAR at shin height threads its beams between the four legs.
// Four maps side by side: each sensor's own grid, the two fused by
// p = max(p_sonar, p_lidar), and one grid fed both streams. The reader moves
// the LiDAR's beam count and watches the summed table appear or vanish while
// the max-fused table stays. Every number shown comes from the wasm core;
// this module only draws and forwards input.
//
// Attributes (see `attributeSpec` below and the README's "Embedding"):
// lidar-beams, seed, scene, autoplay, scans, map-width, controls.
import { startWidget } from './lib/start.js';
import { COLORS } from './lib/chart.js';
import {
  el, slider, button, showError, clearError,
  frameLoop, prefersReducedMotion, fixed, grouped, pacer, showPlaying, setText, nextTask,
} from './lib/ui.js';
import { exportButton, exportMap, followPaneVisibility, followResize, pointerCell, resetPaneSizes, sizePanes } from './lib/pane.js';
import { drawBeams, drawCones, drawMapImage, drawRobot, layerStack, outlineBox } from './lib/layers.js';
import { applyControls, controlGroups, flag, formatControls, jsonObject, whole } from './lib/attributes.js';
import { copyLinkControl } from './lib/state.js';
import { floatingReadout, followCellPointer, mapStage, placeReadout } from './lib/cell-pointer.js';
import { FRAME_WORK_MS, workBudget } from './lib/work-budget.js';

/** Scans per second while playing. */
const STEPS_PER_SECOND = 12;
/** Never more steps per animation frame than this (a slow frame catches up later). */
const MAX_STEPS_PER_FRAME = 4;
/** The first frame's budget, cell visits: about one step of the chapter's scene (173,000, its scans' simulation included), which the first call corrects. */
const FIRST_FRAME_VISITS = 180_000;
/**
 * The least budget of Step's call, cell visits: a step of the chapter's
 * scene fits, so that Step shows its scan before the click returns; a step
 * at a fine resolution stops within its budget and goes on over the frames.
 */
const AT_ONCE_VISITS = 200_000;
/**
 * The core's work per slice of the scans a link asks for before the first
 * frame, milliseconds: each slice is a task of its own, so the page paints
 * and answers input in between.
 */
const SLICE_MS = 25;
/** Largest drawn map, CSS pixels. */
const MAX_CSS_WIDTH = 440;
const FOOTPRINT_COLOR = COLORS.series[3];
const ROBOT_COLOR = COLORS.series[1];

const PANES = [
  { key: 'sonar', title: 'Sonar grid', describe: (r) => `${grouped(r.sonarCount)} cones of ${fixed(r.sonarConeDegrees, 0)}°, at table height` },
  { key: 'lidar', title: 'LiDAR grid', describe: (r) => `${grouped(r.lidarBeams)} beams, at shin height` },
  { key: 'max', title: 'Max fusion', describe: () => 'p = max(p_sonar, p_lidar), eq. 9.9' },
  { key: 'sum', title: 'Summation', describe: () => 'one grid, both streams added' },
];

const GROUPS = ['playback', 'sliders', 'export', 'link'];
const CELL_HINT = 'Point at a cell of any map (a tap on a phone) to read its probability in all four.';

class SensorFusionElement extends HTMLElement {
  static attributeSpec = {
    // The chapter's beam count and the scene's cap are the core's
    // (`constants().sensorFusion`), taken once it has loaded.
    'lidar-beams': {
      type: whole(1, Number.MAX_SAFE_INTEGER), doc: 'beams of the LiDAR’s 360° scan',
      core: (k) => ({ type: whole(1, k.sensorFusion.maxLidarBeams), default: String(k.sensorFusion.defaultLidarBeams) }),
    },
    seed: { type: whole(0, Number.MAX_SAFE_INTEGER), doc: 'seed of the range noise; absent: the chapter’s' },
    scene: { type: jsonObject('{"laps": 2}'), doc: 'fields of the table scene to override (the core checks each); absent: the chapter’s room and table' },
    autoplay: { type: flag(), default: 'on', doc: 'play when first scrolled into view (never under prefers-reduced-motion)' },
    scans: { type: whole(0, 100_000), default: '0', doc: 'scans integrated before the first frame (the run stops at the end of its laps)' },
    'map-width': { type: whole(120, 1200), default: String(MAX_CSS_WIDTH), doc: 'largest width of each of the four maps, CSS pixels' },
    controls: { type: controlGroups(GROUPS), default: 'all', doc: 'control groups shown: playback (play, step, reset), sliders (LiDAR beams), export, link' },
  };

  static observedAttributes = Object.keys(SensorFusionElement.attributeSpec);

  constructor() {
    super();
    this.sim = null;
    this.playing = false;
    this.pace = pacer(STEPS_PER_SECOND, MAX_STEPS_PER_FRAME);
    this.frameBudget = workBudget(FRAME_WORK_MS, FIRST_FRAME_VISITS);
    this.sliceBudget = workBudget(SLICE_MS, FIRST_FRAME_VISITS);
    /** Steps the Step button asked for that are not integrated yet. */
    this.stepsOwed = 0;
    /** Steps the LiDAR's maps still lack after a beam count changed (the core's `rebuilding`). */
    this.rebuilding = 0;
  }

  connectedCallback() {
    // The run is made when the widget first nears the screen: a reader
    // opening the chapter waits for no widget further down.
    return startWidget(this, SensorFusionElement.attributeSpec, {
      build: () => {
        this.values = this.attrs.read();
        this.beams = this.values['lidar-beams'];
        this.build();
        applyControls(this, this.values.controls);
      },
      withCore: (constants) => {
        this.defaultBeams = constants.sensorFusion.defaultLidarBeams;
        this.beamSteps = constants.limits.sensorFusion.beamSteps;
        this.steps = [...this.beamSteps];
        this.beamSlider.input.max = String(this.steps.length - 1);
        this.values = this.attrs.resolve(constants);
        this.beams = this.values['lidar-beams'];
        this.syncSlider();
      },
      whenSeen: async () => {
        this.started = true;
        if ((await this.create()) && this.values.autoplay && !prefersReducedMotion()) this.play();
      },
      ahead: true,
    });
  }

  disconnectedCallback() {
    this.pause();
    this.loop?.stop();
  }

  attributeChangedCallback(name) {
    if (!this.built) return;
    const before = this.values;
    this.values = this.attrs.read();
    const key = (v) => JSON.stringify(v instanceof Set ? [...v] : v);
    if (key(this.values[name]) === key(before[name])) return;
    if (name === 'controls') applyControls(this, this.values.controls);
    else if (name === 'map-width') {
      resetPaneSizes(this.panes);
      this.layout();
    } else if (!this.core || !this.started) return;
    else if (['seed', 'scene', 'scans'].includes(name)) this.create();
    else if (name === 'lidar-beams') this.requestBeams(this.values['lidar-beams']);
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    const v = this.values;
    return {
      'lidar-beams': this.beams, seed: v.seed, scene: v.scene ? JSON.stringify(v.scene) : null,
      autoplay: this.playing ? 'on' : 'off',
      scans: this.reading ? this.reading.step : v.scans,
      'map-width': v['map-width'],
      controls: formatControls(v.controls, GROUPS),
    };
  }

  build() {
    // The beam counts the slider offers, the core's once it has loaded
    // (`constants().limits.sensorFusion.beamSteps`; an attribute may add another).
    this.beamSteps = [];
    this.steps = [];
    this.playButton = button('Play', () => (this.playing ? this.pause() : this.play()), { name: 'play', pressed: false });
    this.beamSlider = slider({
      label: 'LiDAR beams',
      min: 0, max: this.steps.length - 1, step: 1,
      // At the core's beam count once it has loaded (syncSlider).
      value: this.beams === undefined ? 0 : this.steps.indexOf(this.beams),
      format: (i) => (this.steps[i] === undefined ? '' : grouped(this.steps[i])),
      onInput: (i) => this.requestBeams(this.steps[i]),
      name: 'lidar-beams',
    });
    this.status = el('p', { class: 'occgrid-readout sensor-fusion-status', 'aria-live': 'polite' }, 'Loading…');
    this.panes = PANES.map((p) => {
      const canvas = el('canvas', { class: 'occgrid-map sensor-fusion-map', role: 'img', 'aria-label': `${p.title}: not built yet.` });
      const note = el('span', { class: 'sensor-fusion-note' });
      const mean = el('output', { class: 'sensor-fusion-mean', 'aria-live': 'off' }, '–');
      const save = exportButton({
        name: `export-${p.key}`, title: `Save the ${p.title.toLowerCase()} as a ROS map_server PGM + YAML pair`,
        spoken: p.title.toLowerCase(), onClick: () => this.exportMap(p.key),
      });
      const stage = mapStage(canvas);
      followCellPointer(canvas, {
        point: (e) => this.pointAt(p.key, e),
        leave: () => this.pointAt(p.key, null),
        keyboardFocus: () => {},
      });
      const root = el('figure', { class: `sensor-fusion-pane sensor-fusion-${p.key}`, dataset: { map: p.key } },
        el('figcaption', {}, el('strong', {}, p.title), ' ', note),
        stage,
        el('div', { class: 'sensor-fusion-foot' },
          el('span', {}, 'footprint mean occupancy ', mean),
          el('span', { dataset: { controls: 'export' } }, save)));
      return { ...p, canvas, stage, note, mean, root, layers: this.paneLayers(p.key) };
    });
    // One cell of all four maps: eq. 9.9 checked cell by cell.
    this.cellOut = el('p', { class: 'occgrid-readout sensor-fusion-cell', 'aria-live': 'polite' }, CELL_HINT);
    this.cellFloat = floatingReadout();
    this.loop = frameLoop(this, (dt) => this.tick(dt));
    const playback = [
      this.playButton,
      button('Step', () => this.step(), { name: 'step' }),
      button('Reset', () => this.reset(), { name: 'reset' }),
    ];
    for (const b of playback) b.dataset.controls = 'playback';
    this.beamSlider.root.dataset.controls = 'sliders';
    this.append(
      el('div', { class: 'occgrid-controls' }, playback, this.beamSlider.root),
      this.status,
      el('div', { class: 'sensor-fusion-panes' }, this.panes.map((p) => p.root)),
      this.cellOut,
      el('p', { class: 'occgrid-caption' },
        'The dashed outline is the table top. The sonar sees its rim and cannot see past it; the LiDAR sees four legs and free floor between them. ',
        'Both are right about their own slice. Max fusion keeps one map per sensor and takes the more occupied answer per cell, so the table stays an obstacle ',
        '(and a cell stays gray wherever one sensor has not looked yet: unknown, p = 0.5, outranks free). ',
        'Summation adds both streams into one grid as if they measured the same thing: the table’s probability then follows whichever sensor delivers more evidence. ',
        'Lower the beam count and the summed table comes back; the table never changed.'),
      copyLinkControl(this, SensorFusionElement.attributeSpec, () => this.linkState()),
    );
    this.resizer = followResize(this.querySelector('.sensor-fusion-panes'), () => this.layout());
    // A pane off screen is not redrawn; it is brought up to date when seen.
    followPaneVisibility(this.panes, (p) => {
      if (p.stale) this.draw();
    });
  }

  /**
   * A pane's layers over its map: the sonar pane the current cones, the
   * LiDAR pane the current beams, every pane the table's footprint and
   * the robot.
   */
  paneLayers(key) {
    const layers = layerStack();
    if (key === 'sonar') {
      layers.add(({ ctx, s, view }) => drawCones(ctx, s, view.sonar, { color: COLORS.evidence, fillAlpha: '30', outline: 'arc', lineWidth: 1 }));
    }
    if (key === 'lidar') {
      layers.add(({ ctx, s, view }) => drawBeams(ctx, s, [view.robot.x, view.robot.y], view.lidar, { color: COLORS.evidence + '80', lineWidth: 0.75 }));
    }
    layers.add(({ ctx, s, view }) => outlineBox(ctx, s, view.footprint, { color: FOOTPRINT_COLOR, lineWidth: 1.5, dash: [5, 3] }));
    layers.add(({ ctx, s, view }) => drawRobot(ctx, s, view.robot, { color: ROBOT_COLOR, radius: 4, tick: 10, lineWidth: 2 }));
    return layers;
  }

  /**
   * (Re)creates the experiment in the core from the attributes; true once
   * the new run is shown. The core simulates each scan when a step first
   * needs it, so a new run costs a moment; the scans a link asks for
   * before the first frame are integrated in slices, each a task of its
   * own, the count on screen (the run shown stays until they are done).
   * A later create() supersedes this one.
   */
  async create() {
    this.pause();
    const generation = (this.generation = (this.generation ?? 0) + 1);
    const v = this.values;
    let next;
    try {
      let scene;
      if (v.scene || v.seed !== undefined) scene = { ...(v.scene ?? {}), ...(v.seed !== undefined ? { seed: v.seed } : {}) };
      next = new this.core.SensorFusion(scene, undefined);
      // Before the first step: nothing to rebuild.
      if (this.beams !== this.defaultBeams) next.setLidarBeams(this.beams);
      // A link may open the lap part-way through.
      if (v.scans > 0 && !(await this.fastForward(next, v.scans, generation))) {
        next.free();
        return false;
      }
      this.sim?.free();
      this.sim = next;
      this.stepsOwed = 0;
      this.rebuilding = 0;
      clearError(this);
    } catch (e) {
      if (next && next !== this.sim) next.free();
      showError(this, e);
      // With no scene there is nothing to wait for: say so where the
      // status would say how far the lap has got.
      if (!this.sim) {
        this.status.textContent = 'No maps: the scene was refused (see the message above).';
        this.dataset.state = 'refused';
      } else if (this.reading) this.statusText(this.reading);
      return false;
    }
    this.dataset.state = 'ready';
    this.syncSlider();
    this.layout();
    return true;
  }

  /**
   * Integrates the first `target` steps of `sim` (fewer if its lap is
   * shorter) in calls of about SLICE_MS, each in a task of its own; false
   * when a later create() took over.
   */
  async fastForward(sim, target, generation) {
    try {
      for (let done = 0; ;) {
        this.dataset.fastForward = `${done}/${target}`;
        setText(this.status, `Integrating the first ${grouped(target)} scans: ${grouped(done)} done…`);
        await nextTask();
        if (generation !== this.generation) return false;
        const t = performance.now();
        const r = sim.work(target - done, this.sliceBudget.value);
        this.sliceBudget.learn(r.cellVisits, performance.now() - t);
        done = r.step;
        if (done >= target || r.done) return true;
      }
    } finally {
      delete this.dataset.fastForward;
    }
  }

  syncSlider() {
    if (!this.steps.includes(this.beams)) {
      this.steps = [...this.beamSteps, this.beams].sort((a, b) => a - b);
      this.beamSlider.input.max = String(this.steps.length - 1);
    }
    this.beamSlider.set(this.steps.indexOf(this.beams));
  }

  /**
   * Applies the latest requested beam count: the core empties the LiDAR's
   * two maps at once, and the frames that follow rebuild them over the
   * scans so far within the frame's budget, before any new scan (the status
   * says how far the rebuild has got).
   */
  requestBeams(n) {
    this.wantBeams = n;
    // A run still being made takes the count when it starts again.
    if (this.dataset.fastForward !== undefined) {
      this.beams = n;
      this.create();
      return;
    }
    if (this.beamTask || !this.sim) return;
    this.beamTask = setTimeout(() => {
      this.beamTask = null;
      const beams = this.wantBeams;
      try {
        this.sim.setLidarBeams(beams);
        this.beams = beams;
        this.rebuilding = this.sim.readout().rebuilding;
        clearError(this);
      } catch (e) {
        showError(this, e);
      }
      this.syncSlider();
      this.draw();
      if (this.busy()) this.loop.start();
      else this.announce();
    }, 0);
  }

  /** Sizes the canvases to their panes (hi-DPI) and redraws. */
  layout() {
    if (!this.sim) return;
    sizePanes(this.panes, this.sim.width, this.sim.height, this.values['map-width'], 300);
    this.draw();
  }

  play() {
    if (!this.sim || this.playing) return;
    const r = this.sim.readout();
    if (r.step >= r.steps && r.rebuilding === 0) this.sim.reset();
    this.playing = true;
    this.stepsOwed = 0;
    showPlaying(this.playButton, true);
    this.pace.reset();
    // The loop gets frames only while the widget is on screen.
    this.loop.start();
  }

  /** Work left for the frames: playing, steps Step asked for, or a rebuild. */
  busy() {
    return this.playing || this.stepsOwed > 0 || this.rebuilding > 0;
  }

  /**
   * One animation frame, `dt` ms after the previous one: the steps the
   * pace owes (or Step asked for), after what a rebuild still lacks, in one
   * call of the core with the frame's budget (steps the budget left undone
   * stay owed to the next frame), drawn in the next frame: a frame either
   * works or draws, so that on a slow phone neither waits for the other
   * and the page keeps its frame rate.
   */
  tick(dt) {
    if (!this.sim) return false;
    const n = this.playing ? this.pace.take(dt) : Math.min(this.stepsOwed, MAX_STEPS_PER_FRAME);
    if (this.drawOwed) {
      this.drawOwed = false;
      if (this.playing) this.pace.giveBack(n);
      this.draw();
      if (!this.busy()) this.announce();
      return this.busy();
    }
    if (n === 0 && this.rebuilding === 0) return this.busy();
    const report = this.work(n);
    if (!report) return false;
    if (report.done) {
      this.draw();
      this.pause();
      return false;
    }
    this.drawOwed = report.steps + report.rebuilt > 0;
    return true;
  }

  /**
   * One call of the core's work: `n` steps (and what a rebuild lacks first)
   * within the frame's budget, at least `floor` cell visits. Returns the
   * core's report, or null after showing an error.
   */
  work(n, floor = 1) {
    let report;
    try {
      const t = performance.now();
      report = this.sim.work(n, Math.max(floor, this.frameBudget.value));
      this.frameBudget.learn(report.cellVisits, performance.now() - t);
    } catch (e) {
      showError(this, e);
      this.stepsOwed = 0;
      this.pause();
      return null;
    }
    this.rebuilding = report.rebuilding;
    if (this.playing) this.pace.giveBack(n - report.steps);
    else this.stepsOwed = report.done ? 0 : this.stepsOwed - report.steps;
    return report;
  }

  pause() {
    this.loop?.stop();
    // A rebuild or Step's steps go on over the next frames.
    const wasPlaying = this.playing;
    this.playing = false;
    if (this.sim && this.busy()) this.loop.start();
    if (!wasPlaying) return;
    // Steps a frame took and the next was to draw are drawn now.
    if (this.drawOwed) {
      this.drawOwed = false;
      this.draw();
    }
    showPlaying(this.playButton, false);
    this.announce();
  }

  /** Step: one more scan, at once (after a rebuild under way, which the next frames finish first). */
  step() {
    this.pause();
    if (!this.sim) return;
    this.stepsOwed += 1;
    // At once when the step fits AT_ONCE_VISITS (the click shows its
    // scan); a step at a fine resolution goes on over the next frames.
    const report = this.work(this.stepsOwed > 0 ? 1 : 0, AT_ONCE_VISITS);
    this.drawOwed = false;
    this.draw();
    if (report && this.busy()) this.loop.start();
    else this.announce();
  }

  /** Reset: every map back to the prior, the robot to the start. */
  reset() {
    this.pause();
    if (!this.sim) return;
    this.sim.reset();
    this.stepsOwed = 0;
    this.rebuilding = 0;
    this.drawOwed = false;
    this.draw();
    this.announce();
  }

  /** Draws the four maps and the readouts from the core's current state. */
  draw() {
    if (!this.sim) return;
    let r, view;
    try {
      r = this.sim.readout();
      const { width: w, height: h } = this.sim;
      view = this.sim.sceneView();
      for (const p of this.panes) {
        if (!p.ctx) continue;
        p.stale = !p.onScreen;
        if (p.onScreen) {
          drawMapImage(p.canvas, this.memory, this.sim.render(p.key), w, h);
          p.layers.draw({ ctx: p.ctx, s: p.cssW / w, view });
        }
        setText(p.note, `· ${p.describe(r)}`);
        const mean = r.footprint[p.key];
        setText(p.mean, fixed(mean, 3));
        p.mean.dataset.value = String(mean);
        setText(p.canvas,
          `${p.title} (${p.describe(r)}) after ${grouped(r.step)} of ${grouped(r.steps)} scans: mean occupancy over the table’s footprint ${fixed(mean, 3)}. ` +
          'Gray unknown, white free, black occupied; the dashed outline is the table top.', 'aria-label');
      }
    } catch (e) {
      showError(this, e);
      this.pause();
      return;
    }
    this.dataset.step = String(r.step);
    // The beam count and the means are those of finished maps: while the
    // LiDAR's maps are rebuilt, the data attributes keep the last ones.
    if (r.rebuilding > 0) this.dataset.rebuilding = `${r.step - r.rebuilding}/${r.step}`;
    else {
      delete this.dataset.rebuilding;
      this.dataset.lidarBeams = String(r.lidarBeams);
      this.dataset.maxMean = String(r.footprint.max);
      this.dataset.sumMean = String(r.footprint.sum);
    }
    this.reading = r;
    this.readCell();
    if (this.playing) setText(this.status, 'off', 'aria-live');
    this.statusText(r);
  }

  /** The cell under the pointer on map `key` (`e` a pointer event; null: the mouse left the map). */
  pointAt(key, e) {
    if (!this.sim || !e) {
      this.pointed = null;
      return this.readCell();
    }
    this.pointed = { key, ...pointerCell(this.panes.find((p) => p.key === key).canvas, e, this.sim.width, this.sim.height) };
    this.readCell();
  }

  /** Reads the pointed cell of all four maps (the core's numbers), below the maps and over the one pointed at. */
  readCell() {
    const at = this.pointed;
    let c = null;
    try {
      c = at && this.sim ? this.sim.cellAt(at.col, at.row) : null;
    } catch {
      c = null; // off the map: no cell
    }
    if (!c) {
      this.cellOut.textContent = CELL_HINT;
      this.cellFloat.hidden = true;
      for (const k of ['sonar', 'lidar', 'max', 'sum']) delete this.cellOut.dataset[k];
      return;
    }
    const { sonar, lidar, sum } = c;
    setText(this.cellOut,
      `Cell (${sonar.ix}, ${sonar.iy}) at (${fixed(sonar.x, 2)} m, ${fixed(sonar.y, 2)} m)${c.footprint ? ', under the table' : ''}: ` +
      `sonar p = ${fixed(sonar.p, 3)}, LiDAR p = ${fixed(lidar.p, 3)}, max p = ${fixed(c.max, 3)}, summed p = ${fixed(sum.p, 3)} ` +
      `(${grouped(sum.updates)} update${sum.updates === 1 ? '' : 's'} summed).`);
    Object.assign(this.cellOut.dataset, { sonar: String(sonar.p), lidar: String(lidar.p), max: String(c.max), sum: String(sum.p) });
    setText(this.cellFloat, this.cellOut.textContent);
    placeReadout(this.cellFloat, this.panes.find((p) => p.key === at.key).stage, at.row, this.sim.height);
  }

  /** The status line; `announce` writes it again even when unchanged, for a screen reader to hear it. */
  statusText(r, again = false) {
    if (again) this.status.textContent = '';
    setText(this.status,
      `Scan ${grouped(r.step)} of ${grouped(r.steps)}. Mean occupancy over the table’s ${grouped(r.footprintCells)} cells: ` +
      `max fusion ${fixed(r.footprint.max, 3)}, summation ${fixed(r.footprint.sum, 3)} ` +
      `(sonar alone ${fixed(r.footprint.sonar, 3)}, LiDAR alone ${fixed(r.footprint.lidar, 3)}).` +
      (r.rebuilding > 0
        ? ` Rebuilding the LiDAR and summed maps with ${grouped(r.lidarBeams)} beams: ${grouped(r.step - r.rebuilding)} of ${grouped(r.step)} scans.`
        : ''));
  }

  /** Lets screen readers hear the state once the motion stops. */
  announce() {
    this.status.setAttribute('aria-live', 'polite');
    if (this.reading) this.statusText(this.reading, true);
  }

  /** Saves one map as a ROS map_server pair (PGM + YAML, in one zip). */
  exportMap(key) {
    if (this.sim) return exportMap(this, `table-${key}`, () => this.sim.exportMap(key));
  }
}

if (!customElements.get('occgrid-sensor-fusion')) customElements.define('occgrid-sensor-fusion', SensorFusionElement);

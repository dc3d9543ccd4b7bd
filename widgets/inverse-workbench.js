// <occgrid-inverse-workbench>: the hand-crafted inverse sensor model of
// Table 9.2 and the one learned from simulated data (§9.3), for one beam,
// side by side (§9.3; docs/ARCHITECTURE.md, "Sessions and panes").
//
// Two images over the beam's neighbourhood (range along x, bearing offset
// along y) show what one reading adds to each cell, in log odds, on one
// fixed scale (the core's, the same at every reading, stated on the
// legend): white is free, black occupied, mid-gray nothing. Below, both
// models' log odds along the beam axis with their priors l0 (blue). The
// reader moves the reading, tries a max-range reading (a no-return), and
// retrains the learned model with another seed or on denser training maps
// (its l0 follows the maps' density). The core trains the model
// and computes every value drawn; this module lays them out. Nothing moves
// by itself; training waits until the widget is first on screen.
//
// Attributes (see `attributeSpec` below and the README's "Embedding"):
// reading, seed, density, zoom, controls.
import { startWidget } from './lib/start.js';
import { lineChart, COLORS } from './lib/chart.js';
import { el, slider, button, toggle, showError, clearError, hiDpiCanvas, nextId, fixed, grouped, nextTask } from './lib/ui.js';
import { ANY_NUMBER, applyControls, controlGroups, flag, formatControls, parseBounded, steps, whole } from './lib/attributes.js';
import { copyLinkControl } from './lib/state.js';
import { floatingReadout, followCellPointer, mapStage, placeReadout } from './lib/cell-pointer.js';
import { FIRST_TRAIN_UNITS, TRAIN_SLICE_MS, workBudget } from './lib/work-budget.js';

// The reading's and the density's upper bounds are the core's
// (`constants().inverseWorkbench`: the training sensor's z_max, the densest
// training maps it fills); the sliders take them once the core has loaded.
/** Samples of the lattice: one column per 2.5 cm of the full range, bearings every ~1/6 degree. */
const RANGES = 369;
const BEARINGS = 61;
/** How far past z_max the full view reaches, metres (a reading's band lies past it). */
const PAST_MAX = 1.2;
/** Half-width of the zoomed view around the reading, metres. */
const ZOOM = 1.5;
/** Size of each image, CSS pixels. */
const IMAGE_HEIGHT = 150;
const MAX_IMAGE_WIDTH = 520;
const GRID_COLOR = 'rgba(60, 60, 54, 0.55)';
const GROUPS = ['reading', 'zoom', 'retrain', 'link'];
const CELL_HINT = 'Point at a cell of either image (a tap on a phone) to read what one reading adds to it under both models.';
const densityText = (d) => (d === 0 ? 'buildings as drawn' : `boxes to ${Math.round(100 * d)}%`);
/** The chart's four lines; the two priors share the l0 blue, told apart by the dash. */
const SERIES = [
  { label: 'hand-crafted', color: COLORS.series[0] },
  { label: 'learned', color: COLORS.series[1] },
  { label: 'l0 hand-crafted', color: COLORS.l0, dash: [6, 4], width: 1.5 },
  { label: 'l0 learned', color: COLORS.l0, width: 1.5 },
];

const deg = (rad) => (rad * 180) / Math.PI;

class InverseWorkbenchElement extends HTMLElement {
  static attributeSpec = {
    // The sliders' ranges (up to the sensor's z_max and the densest
    // training maps) are the core's (`constants().limits.inverseWorkbench`),
    // taken once it has loaded.
    reading: {
      type: ANY_NUMBER, default: '2.00', doc: 'the reading z, metres (at the sensor’s z_max: a no-return)',
      core: (k) => ({ type: steps(k.limits.inverseWorkbench.reading, 'm') }),
    },
    seed: { type: whole(0, Number.MAX_SAFE_INTEGER), default: '9', doc: 'seed of the learned model’s training data' },
    density: {
      type: ANY_NUMBER, core: (k) => ({ type: steps(k.limits.inverseWorkbench.density) }), default: '0', doc: 'occupied fraction the training maps are filled to with boxes (0: the thin-walled buildings as drawn; 0.45: the chapter’s dense prior)',
    },
    zoom: { type: flag(), default: 'off', doc: `zoom the images to ±${ZOOM} m around the reading` },
    controls: { type: controlGroups(GROUPS), default: 'all', doc: 'control groups shown: reading (slider, max-range button), zoom, retrain (seed, Retrain), link' },
  };

  static observedAttributes = Object.keys(InverseWorkbenchElement.attributeSpec);

  constructor() {
    super();
    this.bench = null;
    this.frame = 0;
    this.zMax = null;
    this.trainBudget = workBudget(TRAIN_SLICE_MS, FIRST_TRAIN_UNITS);
  }

  connectedCallback() {
    // Training takes a few hundred milliseconds of work: it starts when the
    // reader scrolls here, after the status has been painted, and goes in
    // slices that leave the page its frames.
    return startWidget(this, InverseWorkbenchElement.attributeSpec, {
      build: () => {
        this.values = this.attrs.read();
        this.z = this.values.reading;
        this.seed = this.values.seed;
        this.density = this.values.density;
        this.zoom = this.values.zoom;
        this.build();
        applyControls(this, this.values.controls);
      },
      withCore: (constants) => {
        this.zMax = constants.inverseWorkbench.zMax;
        this.readingSlider.setRange(constants.limits.inverseWorkbench.reading);
        this.densitySlider.setRange(constants.limits.inverseWorkbench.density);
        // The reading and density checked against the core's bounds.
        this.values = this.attrs.resolve(constants);
        this.density = this.values.density;
        this.densitySlider.set(this.density);
        this.setReading(this.values.reading);
        // What Reset returns to: the workbench as the page (or link) opened it.
        this.start = { z: this.values.reading, zoom: this.values.zoom, seed: this.values.seed, density: this.values.density };
      },
      whenSeen: () => this.later(() => this.train(this.seed)),
    });
  }

  disconnectedCallback() {
    if (this.frame) cancelAnimationFrame(this.frame);
    this.frame = 0;
  }

  /**
   * An attribute changed: a bad value is only reported (the widget keeps
   * what it shows); a good one is applied, and only that one.
   */
  attributeChangedCallback(name) {
    if (!this.built) return;
    this.values = this.attrs.read();
    if (this.attrs.errors.some((m) => m.startsWith(`invalid ${name}:`))) return;
    const v = this.values[name];
    if (name === 'controls') applyControls(this, v);
    else if (name === 'reading') this.setReading(v);
    else if (name === 'zoom') {
      this.zoom = v;
      this.zoomToggle.input.checked = v;
      this.requestDraw();
    } else if (name === 'density') {
      this.densitySlider.set(v);
      if (this.bench && v !== this.info?.run.density) this.retrainDensity(v);
    } else if (name === 'seed') {
      this.seed = v;
      this.seedInput.value = String(v);
      // Before the first training the new seed is simply the one used.
      if (this.bench && v !== this.info?.run.seed) this.retrain();
    }
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    return {
      reading: this.z.toFixed(2),
      seed: this.info?.run.seed ?? this.seed,
      density: String(this.info?.run.density ?? this.density),
      zoom: this.zoom ? 'on' : 'off',
      controls: formatControls(this.values.controls, GROUPS),
    };
  }

  build() {
    this.readingSlider = slider({
      // The core's range (up to its z_max), set once the core has loaded.
      label: 'Reading z', min: 0, step: 'any', value: this.z,
      format: (v) => `${v.toFixed(2)} m`,
      onInput: (v) => { this.z = v; this.requestDraw(); },
      name: 'reading',
    });
    this.maxButton = button('Max-range reading', () => { if (this.zMax) this.setReading(this.zMax); }, {
      name: 'max-range', title: 'A no-return: the reading sits at the sensor’s maximum range', pressed: false,
    });
    this.resetButton = button('Reset', () => this.reset(), { name: 'reset', title: 'Back to the reading, zoom, seed and density the workbench opened with' });
    this.resetButton.dataset.controls = 'reading';
    this.zoomToggle = toggle(`Zoom to ±${ZOOM} m around the reading`, this.zoom, (on) => { this.zoom = on; this.requestDraw(); }, { name: 'zoom' });
    const seedId = nextId('seed');
    this.seedInput = el('input', { id: seedId, type: 'number', min: 0, step: 1, value: this.seed, name: 'seed', inputmode: 'numeric', class: 'inverse-workbench-seed' });
    this.seedInput.addEventListener('keydown', (e) => { if (e.key === 'Enter') this.retrain(); });
    this.retrainButton = button('Retrain', () => this.retrain(), { name: 'retrain', title: 'Sample 24,000 new training triplets with this seed and fit the model again' });
    this.status = el('p', { class: 'occgrid-readout inverse-workbench-status', 'aria-live': 'polite' }, 'Training the learned model…');
    // A refused seed or density, beside the summary of the model that stays.
    this.refusal = el('p', { class: 'inverse-workbench-refusal', role: 'alert', hidden: true });
    this.l0Out = el('output', { class: 'inverse-workbench-l0' }, '–');
    this.densitySlider = slider({
      label: 'Training-map density', min: 0, max: 1, step: 'any', value: this.density,
      format: densityText, name: 'density',
    });
    // Retraining takes a tenth of a second: on release (or each key press),
    // not on every pixel of a drag.
    this.densitySlider.input.addEventListener('change', () => this.retrainDensity(this.densitySlider.value));
    this.densitySlider.root.dataset.controls = 'retrain';
    this.scaleText = el('p', { class: 'occgrid-caption inverse-workbench-scale-text' });

    const pane = (key, title) => {
      const canvas = el('canvas', { class: 'inverse-workbench-image', role: 'img', 'aria-label': `${title} inverse model: what one reading adds to the cells around the beam; not drawn yet.` });
      const note = el('span', { class: 'inverse-workbench-note' });
      const free = el('output', { class: 'inverse-workbench-free', 'aria-live': 'off' }, '–');
      const stage = mapStage(canvas);
      followCellPointer(canvas, {
        point: (e) => this.pointAt(key, e),
        leave: () => this.pointAt(key, null),
        keyboardFocus: () => {},
      });
      const root = el('figure', { class: `inverse-workbench-pane inverse-workbench-${key}` },
        el('figcaption', {}, el('strong', {}, title), ' ', note),
        stage,
        el('p', { class: 'inverse-workbench-foot' }, 'mean free evidence in front of the reading: ', free));
      return { key, title, canvas, stage, note, free, root };
    };
    this.panes = [pane('hand', 'Hand-crafted (Table 9.2)'), pane('learned', 'Learned (§9.3)')];
    // One cell of both images: what one reading adds to it under each model.
    this.cellOut = el('p', { class: 'occgrid-readout inverse-workbench-cell', 'aria-live': 'polite' }, CELL_HINT);
    this.cellFloat = floatingReadout();
    this.legend = el('canvas', { class: 'inverse-workbench-legend', role: 'img', 'aria-label': 'Colour scale of the two images: white free, mid-gray no evidence, black occupied.' });
    this.chartTitle = el('p', { class: 'inverse-workbench-chart-title' });
    this.chartBox = el('div', { class: 'inverse-workbench-chart', role: 'img', 'aria-label': 'Log odds along the beam axis: not drawn yet.' });
    this.readingSlider.root.dataset.controls = 'reading';
    this.maxButton.dataset.controls = 'reading';
    this.zoomToggle.root.dataset.controls = 'zoom';
    this.retrainButton.dataset.controls = 'retrain';

    this.append(
      el('div', { class: 'occgrid-controls' }, this.readingSlider.root, this.maxButton, this.zoomToggle.root, this.resetButton),
      el('div', { class: 'occgrid-controls' },
        el('div', { class: 'occgrid-control', dataset: { controls: 'retrain' } }, el('label', { for: seedId }, 'Seed'), this.seedInput),
        this.retrainButton,
        this.densitySlider.root,
        el('span', { class: 'occgrid-readout' }, 'learned l0 = ', this.l0Out)),
      // Not a direct child of the widget: the widget's own error box
      // (widgets/lib/ui.js, showError) is, and clearing it must leave this.
      el('div', { class: 'inverse-workbench-training' }, this.status, this.refusal),
      el('div', { class: 'inverse-workbench-panes' }, this.panes.map((p) => p.root)),
      this.cellOut,
      el('div', { class: 'inverse-workbench-scale' }, this.legend),
      this.scaleText,
      this.chartTitle,
      this.chartBox,
      el('p', { class: 'occgrid-caption' },
        'Each image is one beam seen from above: range to the right, bearing offset up and down (left of the beam is up), ',
        'coloured by the evidence one reading adds to a cell, in log odds net of the model’s prior l0 — white free, black occupied, ',
        'mid-gray nothing, one fixed scale for both models and every reading. Green: the beam axis, the reading, and the edges of each model’s field. ',
        'Table 9.2 is a hard-edged cone with a step at the reading. The learned model was never told an obstacle’s thickness or the beam’s width: ',
        'its free-to-occupied ramp is soft, its occupied band sits a little past the reading, its evidence gathers near the axis, ',
        'and its own l0 is negative — the prior of the maps it was trained on. Try a max-range reading: one training reading in twenty was a ',
        'dropout from a real obstacle, so the learned model hardly trusts a no-return to mean free space. ',
        'The learned l0 is the prior of the training maps: thin-walled buildings are mostly empty floor (about −1.9); ',
        'fill them with boxes using the density slider and l0 follows — at 45% occupied, the chapter’s dense map prior, it lands near −0.3.'),
      copyLinkControl(this, InverseWorkbenchElement.attributeSpec, () => this.linkState()),
    );
    this.chart = lineChart(this.chartBox, {
      xLabel: 'range along the beam axis (m)', yLabel: 'log odds',
      series: SERIES,
      height: 220,
      onMade: (plot) => this.legendSamples(plot),
    });
    if ('ResizeObserver' in window) {
      this.resizer = new ResizeObserver(() => this.requestDraw());
      this.resizer.observe(this.querySelector('.inverse-workbench-panes'));
    }
  }

  /**
   * Draws each legend marker as a short sample of its line, dashed where
   * the line is: as squares, the two priors' markers were the same blue
   * square.
   */
  legendSamples(plot) {
    for (const row of plot.root.querySelectorAll('.u-legend .u-series')) {
      const line = SERIES.find((l) => l.label === row.querySelector('.u-label')?.textContent);
      const m = row.querySelector('.u-marker');
      if (!line || !m) continue;
      m.classList.add('inverse-workbench-marker');
      m.dataset.dash = line.dash ? 'dashed' : 'solid';
      m.style.background = 'none';
      m.style.border = '0';
      m.style.borderTop = `${line.width === 1.5 ? 2 : 3}px ${line.dash ? 'dashed' : 'solid'} ${line.color}`;
      m.style.width = '26px';
      m.style.height = '0';
      m.style.verticalAlign = 'middle';
    }
  }

  /** Runs `task` after the browser has painted what changed so far. */
  later(task) {
    requestAnimationFrame(() => setTimeout(task, 0));
  }

  /** Retrains the learned model, same seed, on training maps filled to `density`. */
  retrainDensity(density) {
    this.status.textContent = `Training on maps of ${densityText(density)}…`;
    this.later(() => this.train(null, density));
  }

  /**
   * Shows why a seed or a density was refused, beside the summary of the
   * model that stays (null: clears it).
   */
  refuse(message) {
    this.refusal.hidden = !message;
    this.refusal.classList.toggle('occgrid-error', Boolean(message));
    this.refusal.textContent = message
      ? `${message}${this.info ? `; the model trained with seed ${this.info.run.seed} stays.` : '.'}`
      : '';
    if (message) console.error(`${this.localName}: ${message}`);
  }

  /**
   * Calls `step(units)` (a training call of the core's: true once trained)
   * with budgets sized to TRAIN_SLICE_MS from the last call's time, each
   * call in a task of its own; true once trained, false when `current()`
   * turns false in between (a newer training took over).
   */
  async inSlices(step, current) {
    for (;;) {
      const t = performance.now();
      const units = this.trainBudget.value;
      const finished = step(units);
      this.trainBudget.learn(units, performance.now() - t);
      if (finished) return true;
      await nextTask();
      if (!current()) return false;
    }
  }

  /**
   * Trains (or retrains) the learned model with `seed`, or on maps of
   * `density` when `seed` is null, in calls of about TRAIN_SLICE_MS with the
   * page painting in between; a training asked for later supersedes this
   * one.
   */
  async train(seed, density) {
    const generation = (this.trainings = (this.trainings ?? 0) + 1);
    // Every training starts from the first call's budget: a unit of its
    // sampling (a triplet drawn, a ray cast through a sampled map) costs
    // far more than one of its fitting (an SGD update), so a budget learned
    // at the end of the last fit would make the next sampling's first call
    // many times too long.
    this.trainBudget = workBudget(TRAIN_SLICE_MS, FIRST_TRAIN_UNITS);
    const current = () => generation === this.trainings;
    this.retrainButton.disabled = true;
    let trained = false;
    let refused = null;
    try {
      if (!this.bench) {
        const job = new this.core.InverseWorkbenchTraining(seed);
        try {
          if (!(await this.inSlices((units) => job.work(units), current))) return;
          this.bench = job.finish();
        } finally {
          job.free();
        }
        density = this.densitySlider.value;
        seed = null;
      }
      if (seed !== null || density !== 0 || this.info) {
        // A retraining goes on inside the workbench; a newer one replaces it.
        if (seed === null) this.bench.startDensity(density);
        else this.bench.startRetrain(seed);
        if (!(await this.inSlices((units) => this.bench.trainWork(units), current))) return;
      }
      this.info = this.bench.readout();
      this.zMax = this.info.zMax;
      this.readingSlider.input.max = String(this.zMax);
      if (this.z > this.zMax) this.setReading(this.zMax);
      clearError(this);
      trained = true;
    } catch (e) {
      refused = e;
    } finally {
      if (current()) this.retrainButton.disabled = false;
    }
    // On an error the current model stays, and so does its summary; the
    // refusal is shown beside it (or, with no model yet, as the widget's
    // error).
    if (!trained) {
      if (this.info) {
        this.status.textContent = this.summary;
        this.refuse(refused && refused.message ? refused.message : String(refused));
      } else {
        showError(this, refused);
        this.status.textContent = 'No model trained.';
      }
      return;
    }
    this.refuse(null);
    const { run, learned } = this.info;
    this.densitySlider.set(run.density);
    this.dataset.density = String(run.density);
    this.l0Out.textContent = fixed(learned.l0, 3);
    this.dataset.seed = String(run.seed);
    this.dataset.learnedL0 = String(learned.l0);
    this.summary =
      `Learned from ${grouped(run.triplets)} triplets in ${grouped(run.maps)} sampled maps (${densityText(run.density)}: ${fixed(100 * run.mapOccupancy, 1)}% occupied), ` +
      `seed ${run.seed}, ${grouped(run.epochs)} epochs of SGD: ${grouped(run.trainMs)} ms ` +
      `(sampling ${grouped(run.sampleMs)} ms, fitting ${grouped(run.fitMs)} ms). ` +
      `Mean free evidence along the axis: ${fixed(learned.freeEvidenceShort, 2)} in front of a ${fixed(learned.shortReading, 0)} m reading, ` +
      `${fixed(learned.freeEvidenceMaxRange, 2)} along a max-range reading.`;
    this.status.textContent = this.summary;
    this.requestDraw();
  }

  /**
   * Retrains with the seed in the seed box, read as the `seed` attribute
   * is: a box left empty or holding anything but a whole number is refused
   * by name, beside the summary of the model that stays.
   */
  retrain() {
    const text = this.seedInput.value;
    let seed;
    try {
      seed = parseBounded(InverseWorkbenchElement.attributeSpec.seed.type, text, 'seed');
    } catch (e) {
      this.refuse(`Seed box: ${e.message}`);
      return;
    }
    this.seed = seed;
    this.status.textContent = `Training with seed ${seed}…`;
    this.later(() => this.train(this.seed));
  }

  /** Back to the workbench as it opened: its reading and zoom at once, its model retrained if the seed or density changed. */
  async reset() {
    const start = this.start;
    if (!start) return;
    this.setReading(start.z);
    this.zoom = start.zoom;
    this.zoomToggle.input.checked = start.zoom;
    this.requestDraw();
    if (!this.bench || !this.info) return;
    this.refuse(null);
    if (this.info.run.density !== start.density) {
      this.densitySlider.set(start.density);
      this.status.textContent = `Training on maps of ${densityText(start.density)}…`;
      await this.train(null, start.density);
    }
    this.seedInput.value = String(start.seed);
    if (this.info.run.seed !== start.seed) {
      this.seed = start.seed;
      this.status.textContent = `Training with seed ${start.seed}…`;
      await this.train(start.seed);
    }
  }

  setReading(z) {
    this.z = z;
    this.readingSlider.set(z);
    this.requestDraw();
  }

  /** One redraw per animation frame, however many inputs arrive. */
  requestDraw() {
    if (this.frame || !this.bench) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      this.draw();
    });
  }

  draw() {
    const info = this.info;
    const span = info.learnedHalfWidth * (4 / 3);
    const lattice = this.zoom
      ? { minRange: Math.max(0, this.z - ZOOM), maxRange: Math.max(0, this.z - ZOOM) + 2 * ZOOM, ranges: 241, maxBearing: span, bearings: BEARINGS }
      : { minRange: 0, maxRange: this.zMax + PAST_MAX, ranges: RANGES, maxBearing: span, bearings: BEARINGS };
    let v;
    try {
      v = this.bench.view(this.z, lattice);
      clearError(this);
    } catch (e) {
      showError(this, e);
      return;
    }
    const atMax = this.z >= this.zMax;
    this.maxButton.setAttribute('aria-pressed', String(atMax));
    const width = Math.max(200, Math.min(MAX_IMAGE_WIDTH, Math.floor(this.panes[0].root.clientWidth || 320)));
    // The core draws both images on their shared scale; the page copies the pixels.
    const images = { hand: v.handImage, learned: v.learnedImage };
    const edges = { hand: info.handHalfWidth, learned: info.learnedHalfWidth };
    const notes = {
      hand: `alpha ${fixed(info.alpha * 100, 0)} cm, beta ${fixed(2 * deg(info.handHalfWidth), 1)}°, l0 ${fixed(v.handL0, 2)}`,
      learned: `field ±${fixed(deg(info.learnedHalfWidth), 2)}°, l0 ${fixed(v.learnedL0, 3)}`,
    };
    const reading = `a reading of ${fixed(this.z, 2)} m${atMax ? ' (max range: a no-return)' : ''}`;
    for (const p of this.panes) {
      this.image(p, width, images[p.key], v, lattice, edges[p.key]);
      p.note.textContent = `· ${notes[p.key]}`;
      const free = p.key === 'hand' ? v.handFree : v.learnedFree;
      const l0 = p.key === 'hand' ? v.handL0 : v.learnedL0;
      p.free.textContent = free === null ? '–' : fixed(free, 3);
      p.free.dataset.value = free === null ? '' : String(free);
      p.canvas.setAttribute('aria-label',
        `${p.title} inverse model: the log odds one reading adds to each cell around the beam, for ${reading}, ` +
        `ranges ${fixed(lattice.minRange, 1)} to ${fixed(lattice.maxRange, 1)} m, bearings within ±${fixed(deg(lattice.maxBearing), 1)}°. ` +
        (free === null
          ? 'The reading is too short to leave free space in front of it. '
          : `Mean free evidence in front of the reading: ${fixed(free, 3)} log odds. `) +
        `Prior l0 ${fixed(l0, 3)}; colour scale ±${fixed(v.scale, 2)} log odds, white free, black occupied.`);
    }
    this.colourBar(width, v.scale);
    this.scaleText.textContent =
      `Colour scale: ±${fixed(v.scale, 2)} log odds, the same at every reading (white −${fixed(v.scale, 2)}, black +${fixed(v.scale, 2)}); ` +
      `the strongest evidence at this reading is ${fixed(v.strongest, 2)}` +
      (v.strongest > v.scale ? ', drawn at the end of the scale.' : '.');
    const xs = Array.from(v.rangeAxis);
    this.chart.setData(xs, Array.from(v.handAxis), Array.from(v.learnedAxis), xs.map(() => v.handL0), xs.map(() => v.learnedL0));
    this.chartTitle.textContent = `Log odds along the beam axis for a reading of ${fixed(this.z, 2)} m${atMax ? ' (max range: a no-return)' : ''}`;
    this.chartBox.setAttribute('aria-label',
      `Log odds along the beam axis for a reading of ${fixed(this.z, 2)} m. Learned: from ${fixed(v.learnedAxis[0], 2)} near the sensor; ` +
      `hand-crafted: ${fixed(v.handAxis[0], 2)}; priors ${fixed(v.handL0, 2)} and ${fixed(v.learnedL0, 2)}.`);
    this.dataset.reading = String(this.z);
    this.dataset.learnedFree = v.learnedFree === null ? '' : String(v.learnedFree);
    this.dataset.handFree = v.handFree === null ? '' : String(v.handFree);
    this.dataset.learnedAxisMean = String(v.learnedAxis.reduce((a, b) => a + b, 0) / v.learnedAxis.length);
    this.dataset.scale = String(v.scale);
    this.lattice = lattice;
    this.readCell();
    this.dataset.state = 'ready';
  }

  /** The lattice sample under the pointer on image `key` (`e` a pointer event; null: the mouse left). */
  pointAt(key, e) {
    const p = this.panes.find((q) => q.key === key);
    if (!e || !p.geom) {
      this.pointed = null;
      return this.readCell();
    }
    const rect = p.canvas.getBoundingClientRect();
    const { left, w, h } = p.geom;
    const x = e.clientX - rect.left - left;
    const y = e.clientY - rect.top;
    this.pointed = x >= 0 && x < w && y >= 0 && y < h ? { key, x: x / w, y: y / h } : null;
    this.readCell();
  }

  /** Reads the pointed sample of both models at the current reading (the core's numbers), below the images and over the one pointed at. */
  readCell() {
    const at = this.pointed;
    const lattice = this.lattice;
    let c = null;
    if (at && lattice && this.bench) {
      const col = Math.min(lattice.ranges - 1, Math.floor(at.x * lattice.ranges));
      const row = Math.min(lattice.bearings - 1, Math.floor(at.y * lattice.bearings));
      try {
        c = this.bench.cellAt(this.z, lattice, col, row);
      } catch (e) {
        showError(this, e);
      }
    }
    if (!c) {
      this.cellOut.textContent = CELL_HINT;
      this.cellFloat.hidden = true;
      for (const k of ['range', 'bearing', 'hand', 'learned']) delete this.cellOut.dataset[k];
      return;
    }
    const model = (m) => `${m.evidence >= 0 ? '+' : '−'}${fixed(Math.abs(m.evidence), 3)} log odds (p(m | z) = ${fixed(m.p, 3)})`;
    this.cellOut.textContent =
      `Range ${fixed(c.range, 2)} m, bearing ${c.bearing >= 0 ? '+' : '−'}${fixed(Math.abs(deg(c.bearing)), 2)}°: ` +
      `hand-crafted adds ${model(c.hand)}, learned ${model(c.learned)}.`;
    Object.assign(this.cellOut.dataset, { range: String(c.range), bearing: String(c.bearing), hand: String(c.hand.evidence), learned: String(c.learned.evidence) });
    this.cellFloat.textContent = this.cellOut.textContent;
    const p = this.panes.find((q) => q.key === at.key);
    placeReadout(this.cellFloat, p.stage, at.y * p.geom.h, p.geom.h + 18);
  }

  /** One model's evidence image (RGBA at `ptr` in wasm memory) with its green overlays and axis ticks. */
  image(p, width, ptr, v, lattice, edge) {
    const { ranges, bearings } = lattice;
    const left = 34;
    const bottom = 18;
    const cssW = width;
    const cssH = IMAGE_HEIGHT + bottom;
    if (p.cssW !== cssW) {
      p.cssW = cssW;
      p.ctx = hiDpiCanvas(p.canvas, cssW, cssH);
    }
    const ctx = p.ctx;
    const w = cssW - left - 14;
    const h = IMAGE_HEIGHT;
    p.geom = { left, w, h };
    if (!p.off || p.off.width !== ranges || p.off.height !== bearings) {
      p.off = document.createElement('canvas');
      p.off.width = ranges;
      p.off.height = bearings;
    }
    const img = new ImageData(new Uint8ClampedArray(this.memory.buffer, ptr, ranges * bearings * 4).slice(), ranges, bearings);
    p.off.getContext('2d').putImageData(img, 0, 0);
    ctx.clearRect(0, 0, cssW, cssH);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(p.off, left, 0, w, h);
    const X = (r) => left + ((r - lattice.minRange) / (lattice.maxRange - lattice.minRange)) * w;
    const Y = (b) => h / 2 - (b / lattice.maxBearing) * (h / 2);
    ctx.save();
    ctx.beginPath();
    ctx.rect(left, 0, w, h);
    ctx.clip();
    ctx.strokeStyle = COLORS.evidence;
    ctx.lineWidth = 1;
    ctx.setLineDash([4, 3]);
    ctx.beginPath();
    ctx.moveTo(left, Y(0));
    ctx.lineTo(left + w, Y(0));
    for (const b of [edge, -edge]) {
      ctx.moveTo(left, Y(b));
      ctx.lineTo(left + w, Y(b));
    }
    ctx.stroke();
    ctx.setLineDash([]);
    // The reading: a thin line, with marks at the top and bottom edges so
    // that it does not hide the cells right at the reading.
    const xz = X(this.z);
    ctx.lineWidth = 1;
    ctx.globalAlpha = 0.6;
    ctx.beginPath();
    ctx.moveTo(xz, 0);
    ctx.lineTo(xz, h);
    ctx.stroke();
    ctx.globalAlpha = 1;
    ctx.fillStyle = COLORS.evidence;
    ctx.beginPath();
    ctx.moveTo(xz - 5, 0);
    ctx.lineTo(xz + 5, 0);
    ctx.lineTo(xz, 7);
    ctx.moveTo(xz - 5, h);
    ctx.lineTo(xz + 5, h);
    ctx.lineTo(xz, h - 7);
    ctx.fill();
    ctx.restore();
    // Ticks: every metre (every 0.5 m when zoomed), and the bearing limits.
    ctx.fillStyle = GRID_COLOR;
    ctx.strokeStyle = GRID_COLOR;
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    const step = this.zoom ? 0.5 : 1;
    let first = true;
    for (let r = Math.ceil(lattice.minRange / step) * step; r <= lattice.maxRange + 1e-9; r += step) {
      ctx.fillRect(X(r), h, 1, 4);
      ctx.fillText(`${Number(r.toFixed(1))}${first ? ' m' : ''}`, X(r) + (first ? 8 : 0), h + 4);
      first = false;
    }
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    ctx.fillText(`+${fixed(deg(lattice.maxBearing), 1)}°`, left - 3, 7);
    ctx.fillText('0°', left - 3, Y(0));
    ctx.fillText(`−${fixed(deg(lattice.maxBearing), 1)}°`, left - 3, h - 7);
  }

  /** The shared log-odds scale under the two images. */
  colourBar(width, scale) {
    const cssW = Math.min(2 * width, 420);
    const cssH = 34;
    if (this.legendW !== cssW) {
      this.legendW = cssW;
      this.legendCtx = hiDpiCanvas(this.legend, cssW, cssH);
    }
    const ctx = this.legendCtx;
    ctx.clearRect(0, 0, cssW, cssH);
    const x0 = 40;
    const w = cssW - 2 * x0;
    const grad = ctx.createLinearGradient(x0, 0, x0 + w, 0);
    grad.addColorStop(0, 'rgb(255,255,255)');
    grad.addColorStop(0.5, 'rgb(128,128,128)');
    grad.addColorStop(1, 'rgb(1,1,1)');
    ctx.fillStyle = grad;
    ctx.fillRect(x0, 2, w, 12);
    ctx.strokeStyle = '#8a8a80';
    ctx.strokeRect(x0 + 0.5, 2.5, w - 1, 11);
    ctx.fillStyle = '#1b1b1b';
    ctx.font = '11px system-ui, sans-serif';
    ctx.textBaseline = 'top';
    ctx.textAlign = 'center';
    ctx.fillText(`−${fixed(scale, 2)} free`, x0 + 30, 17);
    ctx.fillText('0 (log odds)', x0 + w / 2, 17);
    ctx.fillText(`+${fixed(scale, 2)} occupied`, x0 + w - 36, 17);
    this.legend.setAttribute('aria-label', `Colour scale, the same at every reading: white is ${fixed(-scale, 2)} log odds (free), mid-gray 0, black +${fixed(scale, 2)} (occupied)`);
  }
}

if (!customElements.get('occgrid-inverse-workbench')) customElements.define('occgrid-inverse-workbench', InverseWorkbenchElement);

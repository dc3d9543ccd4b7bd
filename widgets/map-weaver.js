// <occgrid-map-weaver>: the apartment lap, live (Probabilistic Robotics
// Table 9.1 with the inverse models of Table 9.2 and §9.3).
//
// A robot drives laps through a simulated apartment with a 60-beam LiDAR
// while two maps are built side by side from the same scans: by default the
// hand-crafted model on the left and the learned one on the right, both at
// the true poses. Either pane can switch model, pose source (oracle or dead
// reckoning), clamp and evidence strength. Readouts: entropy and its curve,
// Brier score against the ground truth, cells visited per scan, time per
// frame, three cells' log odds over time, and any cell under the pointer.
// Every number comes from the wasm core (MapWeaver); this module lays out,
// forwards input and draws: map pixels straight from wasm memory, and the
// robot, its beams and the person over them. The knobs' ranges and the
// attributes' defaults are the core's (`constants().mapWeaver`), and the
// beam counts and cell sizes a pane offers are the run's (its readout's
// `choices`: a scene may have another LiDAR or resolution).
//
// Attributes (see `attributeSpec` below, widgets/lib/map-weaver-attributes.js
// for those the core bounds, and the README's "Embedding"):
// seed, laps, scene, person, speed, autoplay, scans, mode, left-/right-
// model, pose, clamp, strength, mapper, sensor, beta, beams, resolution and
// forget-l0, map-width, controls; for the real-log
// panel (widgets/map-weaver-log.js): log, log-resolution, log-range-cap,
// log-alpha, log-l-occ, log-l-free, log-clamp, log-no-return-reach, log-walls,
// log-poses, log-seed, log-model, log-compare-model.
import { loadLogCore } from './lib/core.js';
import { startWidget } from './lib/start.js';
import { COLORS } from './lib/chart.js';
import { TRACK_COLORS, drawCharts, makeCharts } from './lib/map-weaver-charts.js';
import {
  FIRST_TRAIN_UNITS, FRAME_WORK_MS, TRAIN_SLICE_MS, fastForward, startInSlices, workBudget, workOnce,
} from './lib/work-budget.js';
import {
  el, slider, button, toggle, select, showError, clearError,
  frameLoop, prefersReducedMotion, fixed, nextId, pacer, showPlaying,
} from './lib/ui.js';
import {
  applyControls, controlGroups, flag, formatControls, jsonObject, oneOf, whole,
} from './lib/attributes.js';
import { copyLinkControl } from './lib/state.js';
import { LOG_SPEC, paneSpec } from './lib/map-weaver-attributes.js';
import {
  arrowCell, exportButton, exportMap, followPaneVisibility, followResize, pointerCell, resetPaneSizes, sizePanes,
} from './lib/pane.js';
import { drawBeams, drawHits, drawMapImage, drawRobot, layerStack, outlineBox, outlineCell } from './lib/layers.js';
import {
  MODEL_NAMES, POSE_NAMES, SPOKEN_MODELS, SPOKEN_POSES, CURSOR_HINT, HOVER_HINT, GROUPS, PANE_FIELDS, SIDES, inAttributeTerms, REBUILD_FIELDS, orAbsent, PANE_FORMATS, formatPane, MAPPER_NAMES, LEANINGS, LOG_FIELDS, count, ghostText, linkKeeps, bits, signed, metres,
} from './lib/map-weaver-words.js';
import { followCellPointer, placeReadout } from './lib/cell-pointer.js';
import { showComparison, showPaneReadout } from './lib/map-weaver-readouts.js';
import { brierMap } from './lib/brier-map.js';

const SPEEDS = [0.25, 0.5, 1, 2, 4, 8];
/**
 * The clock budget of one slice of the scans a link asks for before the
 * first frame (the core bounds the total: `checkFastForward`). The budget
 * is in cell visits learned from the last slice's time, and a scan's
 * simulation and readouts cost time no visit counts: 12 ms keeps a slice
 * well under a 50 ms task. A training call gets `TRAIN_SLICE_MS`
 * (widgets/lib/work-budget.js).
 */
const SLICE_MS = 12;
/**
 * A run's maps are drawn in calls of `SLICE_MS`, the first of this many
 * cells (a cell of a view synced; the scene's largest size has two views of
 * a million), which its time corrects.
 */
const FIRST_BUILD_CELLS = 50_000;
/** Never more scans per animation frame than this (a slow frame catches up later). */
const MAX_SCANS_PER_FRAME = 16;
/**
 * The least budget of a call made at once on Step or a knob, cell visits:
 * a scan of the chapter's apartment in both panes (9,600) fits, so there
 * Step is done before the click returns; a fine grid's sweep is not.
 */
const AT_ONCE_VISITS = 50_000;
/** Least time between two chart redraws while playing, ms. */
const CHART_EVERY_MS = 150;
const MAX_CSS_WIDTH = 480;

const ROBOT_COLOR = COLORS.series[1];
const PERSON_COLOR = '#d01c8b';

class MapWeaverElement extends HTMLElement {
  static attributeSpec = {
    // The chapter run's seed, laps and person, and the most laps a run may
    // have, are the core's (`constants().mapWeaver`), taken once it has loaded.
    seed: {
      type: whole(0, Number.MAX_SAFE_INTEGER), core: (c) => ({ default: String(c.mapWeaver.defaults.seed) }),
      doc: 'seed of the simulation: odometry noise, range noise, the person’s walk',
    },
    laps: {
      type: whole(1, Number.MAX_SAFE_INTEGER), core: (c) => ({ type: whole(1, c.mapWeaver.maxLaps), default: String(c.mapWeaver.defaults.laps) }),
      doc: 'laps in the run',
    },
    scene: { type: jsonObject('{"scan_rate": 12}'), doc: 'fields of the apartment scene to override (the core checks each); absent: the chapter’s apartment' },
    person: { type: flag(), core: (c) => ({ default: c.mapWeaver.defaults.person ? 'on' : 'off' }), doc: 'a person walking the corridor' },
    speed: { type: oneOf(SPEEDS.map(String), Number), default: '1', doc: 'playback speed: 1 is real time, at the scene’s scan rate' },
    autoplay: { type: flag(), default: 'on', doc: 'play when first scrolled into view (never under prefers-reduced-motion)' },
    scans: { type: whole(0, 1_000_000), default: '0', doc: 'scans integrated before the first frame (the run stops at its last lap)' },
    mode: { type: oneOf(['sim', 'log']), default: 'sim', doc: 'the simulated apartment or the real-log panel' },
    'brier-map': { type: flag(), default: 'off', doc: 'show, under the maps, where each is closer to the ground truth: the per-cell Brier difference (exercise 8)' },
    situation: { type: oneOf(['lap', 'ghost-watch']), default: 'lap', doc: 'the robot’s lap, or exercise 5’s ghost watch: the robot parked in the corridor while the person stands by the kitchen door, then leaves' },
    ...paneSpec('left', 0),
    ...paneSpec('right', 1),
    'map-width': { type: whole(120, 1200), default: String(MAX_CSS_WIDTH), doc: 'largest width of each map, CSS pixels (a narrow column shrinks them)' },
    ...LOG_SPEC,
    controls: { type: controlGroups(GROUPS), default: 'all', doc: 'control groups shown: data (simulation / real log), playback (play, step, reset, speed), toggles (person, the robot’s lap or ghost watch, each map’s model, pose source, mapper, sensor, beams, resolution and forget-l0 switch), sliders (clamp, strength, cone opening), log-source (real-log file picker and menu), log-settings (real-log resolution and model sliders), export, link' },
  };

  static observedAttributes = Object.keys(MapWeaverElement.attributeSpec);

  constructor() {
    super();
    this.weaver = null;
    this.playing = false;
    // Speed 1 is real time: the rate is the session's scans per second
    // (`scanRate`), passed with each frame, since a new scene may change it.
    this.pace = pacer(1, MAX_SCANS_PER_FRAME);
    this.frameBudget = workBudget(FRAME_WORK_MS, AT_ONCE_VISITS);
    this.sliceBudget = workBudget(SLICE_MS, AT_ONCE_VISITS);
    this.trainBudget = workBudget(TRAIN_SLICE_MS, FIRST_TRAIN_UNITS);
    this.buildBudget = workBudget(SLICE_MS, FIRST_BUILD_CELLS);
    /** Scans Step asked for that are not integrated yet. */
    this.stepsOwed = 0;
    this.cursor = null; // { pane, col, row } under the pointer or keyboard
  }

  connectedCallback() {
    return startWidget(this, MapWeaverElement.attributeSpec, {
      build: () => {
        this.values = this.attrs.read();
        // The person and the panes' settings wait for the core's defaults.
        this.options = { speed: this.values.speed, person: null, panes: null };
        this.build();
        applyControls(this, this.values.controls);
      },
      withCore: (constants) => {
        this.limits = constants.mapWeaver;
        this.logLimits = constants.limits.realLog;
        this.values = this.attrs.resolve(constants);
        this.options.person = this.values.person;
        this.options.panes = SIDES.map((side) => this.paneOptions(side));
        this.applyLimits();
        this.syncControls();
        if (this.values.mode === 'log') this.setMode('log');
      },
      whenSeen: async () => {
        this.started = true;
        await this.create();
        if (this.weaver && this.values.autoplay && !prefersReducedMotion() && this.mode === 'sim') this.play();
      },
    });
  }

  disconnectedCallback() {
    this.pause();
    this.loop?.stop();
  }

  /** One pane's settings from the attributes. */
  paneOptions(side) {
    const o = {};
    for (const [attr, field] of Object.entries(PANE_FIELDS)) o[field] = this.values[`${side}-${attr}`];
    o.beams ??= null;
    o.resolution ??= null;
    return o;
  }

  attributeChangedCallback(name) {
    if (!this.built) return;
    const before = this.values;
    this.values = this.attrs.read();
    const value = this.values[name];
    const same = JSON.stringify(value instanceof Set ? [...value] : value) === JSON.stringify(before[name] instanceof Set ? [...before[name]] : before[name]);
    if (same) return;
    if (name === 'controls') applyControls(this, value);
    else if (name === 'log') {
      if (value && this.realLog) this.realLog.open(value);
    } else if (name in LOG_FIELDS) this.realLog?.setSettings({ [LOG_FIELDS[name].field]: value });
    else if (name === 'speed') {
      this.options.speed = value;
      this.speedSelect.input.value = String(value);
    } else if (!this.limits) return; // read again once the core's bounds are in
    else if (name === 'person') this.setPerson(value);
    else if (name === 'brier-map') this.showBrierMap(value);
    else if (name === 'mode') this.setMode(value);
    else if (name === 'map-width') {
      resetPaneSizes(this.panes);
      this.layout();
    } else if (/^(left|right)-/.test(name)) {
      const k = name.startsWith('left') ? 0 : 1;
      const field = PANE_FIELDS[name.replace(/^(left|right)-/, '')];
      this.setPane(k, { [field]: value ?? (field === 'beams' || field === 'resolution' ? null : value) });
    } else if (['seed', 'laps', 'situation', 'scene', 'scans'].includes(name) && this.started) this.create();
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    const o = this.options;
    // Before the core has loaded: what the attributes say.
    const person = o.person ?? this.values.person;
    const panes = o.panes ?? SIDES.map((side) => this.paneOptions(side));
    const state = {
      seed: this.values.seed, laps: this.values.laps, situation: this.values.situation,
      scene: this.values.scene ? JSON.stringify(this.values.scene) : null,
      person: person === undefined ? null : person ? 'on' : 'off', speed: o.speed,
      autoplay: this.playing ? 'on' : 'off',
      scans: this.reading ? this.reading.scans : this.values.scans,
      mode: this.mode,
      'map-width': this.values['map-width'],
      'brier-map': this.brierMap.on ? 'on' : 'off',
      controls: formatControls(this.values.controls, GROUPS),
    };
    SIDES.forEach((side, k) => {
      for (const [attr, field] of Object.entries(PANE_FIELDS)) {
        const v = panes[k][field];
        state[`${side}-${attr}`] = v === undefined ? null : formatPane(field, v);
      }
    });
    return { ...state, ...this.logLinkState() };
  }

  /**
   * The real-log attributes for a link: the panel's state once it exists
   * (the log it shows when that came from /datasets/, and its settings),
   * else what the attributes say.
   */
  logLinkState() {
    const panel = this.realLog?.linkState();
    const state = { log: panel ? panel.log : this.values.log };
    for (const [attr, { field, format }] of Object.entries(LOG_FIELDS)) {
      state[attr] = format(panel ? panel.settings[field] : this.values[attr]);
    }
    return state;
  }

  /** The real-log panel's starting state from the attributes. */
  logOptions() {
    const settings = {};
    for (const [attr, { field }] of Object.entries(LOG_FIELDS)) settings[field] = this.values[attr];
    return { settings, log: this.values.log ?? null, limits: this.logLimits };
  }

  // ---- layout ------------------------------------------------------------

  build() {
    this.mode = 'sim';
    const group = nextId('map-weaver-mode');
    this.radios = {};
    const radio = (value, label, checked) => {
      const id = nextId('map-weaver-mode');
      const input = el('input', { type: 'radio', name: group, id, value });
      input.checked = checked;
      input.addEventListener('change', () => input.checked && this.setMode(value));
      this.radios[value] = input;
      return el('span', { class: 'map-weaver-mode-option' }, input, el('label', { for: id }, label));
    };
    const modes = el('fieldset', { class: 'map-weaver-mode', dataset: { controls: 'data' } },
      el('legend', {}, 'Data'),
      radio('sim', 'Simulated apartment', true),
      radio('log', 'Real log', false));

    this.playButton = button('Play', () => (this.playing ? this.pause() : this.play()), { name: 'play', pressed: false });
    this.speedSelect = select('Speed', SPEEDS.map((s) => [String(s), `${s}×`]), String(this.options.speed),
      (v) => { this.options.speed = Number(v); }, { name: 'speed' });
    this.personToggle = toggle('Person in the corridor', false, (on) => this.setPerson(on), { name: 'person' });
    this.situationSelect = select('Robot', [['lap', 'drives its lap'], ['ghost-watch', 'parked: ghost watch']], 'lap',
      (v) => this.setAttribute('situation', v), { name: 'situation' });
    this.status = el('p', { class: 'occgrid-readout map-weaver-status', 'aria-live': 'polite' }, 'Loading the core…');
    this.loop = frameLoop(this, (dt) => this.tick(dt));

    this.panes = SIDES.map((side, k) => this.buildPane(side, k));
    // The cell readout floats over the map pointed at; the hint stays below.
    this.hover = el('p', { class: 'occgrid-readout map-weaver-hover', 'aria-live': 'polite', hidden: true }, HOVER_HINT);
    this.hoverHint = el('p', { class: 'occgrid-caption map-weaver-hover-hint' }, HOVER_HINT);
    this.comparison = el('p', { class: 'occgrid-readout map-weaver-comparison', hidden: true });
    this.brierMap = brierMap((on) => this.setAttribute('brier-map', on ? 'on' : 'off'));
    this.entropyBox = el('div', { class: 'map-weaver-chart map-weaver-entropy-chart', role: 'img', 'aria-label': 'Map entropy over time: no scans yet.' });

    const playback = [
      this.playButton,
      button('Step', () => this.step(), { name: 'step', title: 'Integrate one scan' }),
      button('Reset', () => this.reset(), { name: 'reset', title: 'Start the lap again with the current settings' }),
      this.speedSelect.root,
    ];
    for (const c of playback) c.dataset.controls = 'playback';
    for (const c of [this.personToggle.root, this.situationSelect.root]) c.dataset.controls = 'toggles';
    this.simPanel = el('div', { class: 'map-weaver-sim' },
      el('div', { class: 'occgrid-controls' }, playback, this.personToggle.root, this.situationSelect.root),
      this.status,
      el('div', { class: 'map-weaver-panes' }, this.panes.map((p) => p.root)),
      this.comparison,
      this.brierMap.root,
      this.hoverHint,
      this.entropyBox,
      el('p', { class: 'occgrid-caption' },
        'Gray is unknown (the prior), white free, black occupied. Green lines are the current scan’s beams, drawn from where the pane believes the robot is; ',
        'the hollow ring marks where it truly is. The magenta square is the person: the LiDAR sees them, so the map gets a ghost where they stood, ',
        'and only later scans through that spot can erase it. The clamp caps how sure a cell can get, and with it how many contradicting scans a ghost needs to fade. ',
        'Switch a pane to dead reckoning and its map is rebuilt from the same scans at the odometry’s poses: walls double and the corridor bends. ',
        'The far halves of the two north rooms and the closet are never seen and stay at the prior. ',
        'Every knob of a pane (model, pose source, clamp, strength, mapper, sensor, β, beams, cells) rebuilds it over the scans so far, ',
        'a slice each frame: the map shows what that setting gives for the same scans, and a knob turned and turned back gives the same map again.'),
      el('details', { class: 'occgrid-caption map-weaver-explain' },
        el('summary', {}, 'What the readouts mean'),
        el('ul', {},
          el('li', {}, el('strong', {}, 'Entropy'), ': the sum over all cells of each cell’s binary entropy, in bits: 1 bit for a cell at p = 0.5, near 0 for a cell the map is sure of. It falls as the map fills in.'),
          el('li', {}, el('strong', {}, 'Brier'), ' score: the mean of (p − truth)² over the part of the map the lap surveys (the corridor, the two south rooms and their walls), truth 1 for an occupied cell of the simulated apartment and 0 for a free one. 0 is a perfect map; a map still all at p = 0.5 scores 0.25.'),
          el('li', {}, el('strong', {}, 'Cells visited per scan'), ': how many cells the last scan’s beams looked at (Table 9.1 runs only over the cells in a beam’s perceptual field, not the whole map): the work one scan costs.'),
          el('li', {}, el('strong', {}, 'Core time per frame'), ': milliseconds the core spent integrating the scans of the last animation frame (several per frame at higher speeds), as this browser measured it.'))));

    this.logPanel = el('div', { class: 'map-weaver-log-host', hidden: true });
    this.append(modes, this.simPanel, this.logPanel,
      copyLinkControl(this, MapWeaverElement.attributeSpec, () => this.linkState(), () => linkKeeps(this.mode, this.realLog)));

    this.resizer = followResize(this.querySelector('.map-weaver-panes'), () => this.layout());
    // A pane off screen is not redrawn; it is brought up to date when seen.
    followPaneVisibility(this.panes, () => this.draw());
  }

  buildPane(side, k) {
    const title = el('strong', {}, side === 'left' ? 'Left map' : 'Right map');
    const note = el('span', { class: 'map-weaver-note' });
    const canvas = el('canvas', {
      class: 'occgrid-map map-weaver-map', tabindex: 0, role: 'img',
      'aria-label': `${side === 'left' ? 'Left' : 'Right'} map, not built yet. ${CURSOR_HINT}`,
    });
    const stage = el('div', { class: 'map-weaver-stage' }, canvas);
    // The knobs take their ranges and values once the core has loaded
    // (applyLimits, syncControls) and their menus once the run exists
    // (fillChoices); until then they are hidden.
    const learned = toggle('Learned model', false, (on) => this.setPane(k, { model: on ? 'learned' : 'hand-crafted' }), { name: `learned-${side}` });
    const oracle = toggle('Pose oracle', false, (on) => this.setPane(k, { pose: on ? 'oracle' : 'dead-reckoning' }), { name: `oracle-${side}` });
    const clamp = slider({
      label: 'Clamp l_max', format: (v) => fixed(v, 1),
      onInput: (v) => this.setPane(k, { clamp: v }), name: `clamp-${side}`,
    });
    const strength = slider({
      label: 'Evidence strength', format: (v) => `${fixed(v, 2)}×`,
      onInput: (v) => this.setPane(k, { strength: v }), name: `strength-${side}`,
    });
    const mapper = select('Mapper', [['traversal', 'Ray traversal'], ['sweep', 'Every-cell sweep (Table 9.1)']], 'traversal',
      (v) => this.setPane(k, { mapper: v }), { name: `mapper-${side}` });
    const sensor = select('Sensor', [['lidar', 'Thin LiDAR beams'], ['cone', 'Cone of opening β']], 'lidar',
      (v) => this.setPane(k, { sensor: v }), { name: `sensor-${side}` });
    const beta = slider({
      label: 'Cone opening β', format: (v) => `${fixed(v, 0)}°`,
      onInput: (v) => this.setPane(k, { betaDeg: v }), name: `beta-${side}`,
    });
    // Each option is a value the pane may use; choosing it sends the
    // setting that asks for it (none for the scene's own).
    const settingOf = (menu, v) => this.choices?.[menu].find((c) => String(c.value) === v)?.setting ?? null;
    const beams = select('Beams', [], '', (v) => this.setPane(k, { beams: settingOf('beams', v) }), { name: `beams-${side}` });
    const resolution = select('Cells', [], '', (v) => this.setPane(k, { resolution: settingOf('resolutions', v) }), { name: `resolution-${side}` });
    const forget = toggle('Forget to subtract l0', false, (on) => this.setPane(k, { forgetL0: on }), { name: `forget-l0-${side}` });
    // Both panes have these controls: their names say which pane.
    const whose = side === 'left' ? 'left map' : 'right map';
    learned.input.setAttribute('aria-label', `Learned model, ${whose}`);
    oracle.input.setAttribute('aria-label', `Pose oracle, ${whose}`);
    clamp.input.setAttribute('aria-label', `Clamp l_max, ${whose}`);
    strength.input.setAttribute('aria-label', `Evidence strength, ${whose}`);
    mapper.input.setAttribute('aria-label', `Mapper, ${whose}`);
    sensor.input.setAttribute('aria-label', `Sensor, ${whose}`);
    beta.input.setAttribute('aria-label', `Cone opening β, ${whose}`);
    beams.input.setAttribute('aria-label', `Beams, ${whose}`);
    resolution.input.setAttribute('aria-label', `Cell size, ${whose}`);
    forget.input.setAttribute('aria-label', `Forget to subtract l0, ${whose}`);
    learned.root.dataset.controls = 'toggles';
    oracle.root.dataset.controls = 'toggles';
    clamp.root.dataset.controls = 'sliders';
    strength.root.dataset.controls = 'sliders';
    for (const c of [mapper.root, sensor.root, beams.root, resolution.root, forget.root]) c.dataset.controls = 'toggles';
    beta.root.dataset.controls = 'sliders';
    const out = (cls) => el('output', { class: `map-weaver-value map-weaver-${cls}` }, '–');
    const entropy = out('entropy');
    const brier = out('brier');
    const visited = out('visited');
    const scanMs = out('scan-ms');
    const ghost = el('p', { class: 'occgrid-readout map-weaver-ghost' }, 'Ghost: none has faded yet.');
    const save = exportButton({
      name: `export-${side}`, title: `Save the ${side} map as a ROS map_server PGM + YAML pair`,
      spoken: side, onClick: () => this.exportMap(k),
    });
    const chartBox = el('div', { class: 'map-weaver-chart map-weaver-tracked-chart', role: 'img', 'aria-label': `${side === 'left' ? 'Left' : 'Right'} map: three cells’ log odds over time, no scans yet.` });
    const knobs = el('div', { class: 'occgrid-controls map-weaver-knobs', hidden: true }, learned.root, oracle.root, clamp.root, strength.root,
      mapper.root, sensor.root, beta.root, beams.root, resolution.root, forget.root);
    const root = el('figure', { class: `map-weaver-pane map-weaver-${side}`, dataset: { pane: String(k) } },
      el('figcaption', {}, title, ' ', note),
      stage,
      el('div', { class: 'map-weaver-readouts occgrid-readout' },
        el('span', {}, 'Entropy ', entropy, ' bits'),
        el('span', {}, 'Brier ', brier),
        el('span', {}, 'Cells visited ', visited, ' per scan'),
        el('span', {}, 'Core time ', scanMs, ' ms per scan')),
      ghost,
      knobs,
      chartBox,
      el('div', { class: 'map-weaver-foot', dataset: { controls: 'export' } }, save));
    const pane = {
      side, k, root, canvas, stage, note, knobs, learned, oracle, clamp, strength, mapper, sensor, beta, beams, resolution, forget,
      entropy, brier, visited, scanMs, ghost, chartBox, layers: this.paneLayers(k),
    };
    followCellPointer(canvas, {
      point: (e) => this.pointAt(pane, e),
      leave: () => { this.cursor = null; this.draw(); },
      keyboardFocus: () => {
        if (!this.cursor || this.cursor.pane !== k) this.cursor = this.startCell(k);
        this.draw();
      },
    });
    canvas.addEventListener('blur', () => { if (this.cursor?.pane === k) { this.cursor = null; this.draw(); } });
    canvas.addEventListener('keydown', (e) => this.keyCursor(pane, e));
    return pane;
  }

  /**
   * A pane's layers over its map: the beams from where the pane believes
   * the robot is and their hits, the person, the tracked cells, the
   * cursor, and the robot (with a ring where it truly is: the two differ
   * under dead reckoning).
   */
  paneLayers(k) {
    const layers = layerStack();
    layers.add(({ ctx, s, o }) => drawBeams(ctx, s, [o.robot.x, o.robot.y], o.beams, { color: COLORS.evidence + 'b0', lineWidth: 0.8, count: o.hits.length }));
    layers.add(({ ctx, s, o }) => drawHits(ctx, s, o.beams, o.hits, { color: COLORS.evidence, size: 3 }));
    layers.add(({ ctx, s, o }) => o.person && outlineBox(ctx, s, o.person, { color: PERSON_COLOR, lineWidth: 2, fillAlpha: '55' }));
    layers.add(({ ctx, s, o }) => o.tracked.forEach((cell, i) => outlineCell(ctx, s, cell, { color: TRACK_COLORS[i], lineWidth: 2, pad: 2 })));
    layers.add(({ ctx, s }) => {
      if (this.cursor && this.cursor.pane === k) outlineCell(ctx, s, this.cursor, { color: COLORS.l0, lineWidth: 2 });
    });
    layers.add(({ ctx, s, o }) => drawRobot(ctx, s, o.robot, {
      color: ROBOT_COLOR, radius: 4, tick: o.tick * s, lineWidth: 2.5, truth: o.truth, ringRadius: 6, ringWidth: 1.5,
    }));
    return layers;
  }

  /** Shows or hides the per-cell Brier difference under the maps. */
  showBrierMap(on) {
    this.brierMap.set(on);
    this.draw(true);
  }

  /** Sizes the canvases to their panes (hi-DPI) and redraws. */
  layout() {
    if (!this.weaver) return;
    sizePanes(this.panes, this.weaver.width, this.weaver.height, this.values['map-width'], 320);
    this.draw(true);
  }

  makeCharts() {
    makeCharts(this);
  }

  // ---- the core ----------------------------------------------------------

  /** (Re)creates the run from the attributes. Training the learned model takes a moment. */
  async create() {
    this.pause();
    // A later create() (an attribute changed meanwhile) supersedes this one.
    const generation = (this.generation = (this.generation ?? 0) + 1);
    this.status.textContent = 'Training the learned inverse model…';
    // Let the message paint before the core works for a moment.
    await nextTask();
    if (generation !== this.generation) return;
    const v = this.values;
    let next;
    let caughtUp = false;
    try {
      const settings = { seed: v.seed, laps: v.laps, situation: v.situation, person: this.options.person, panes: this.options.panes.map((o) => ({ ...o })) };
      if (v.scene) settings.scene = v.scene;
      // The learned model trains in slices (once per page for the same
      // settings), each training from the first call's budget: a unit of
      // sampling costs far more than one of fitting, where the last ended.
      this.trainBudget = workBudget(TRAIN_SLICE_MS, FIRST_TRAIN_UNITS);
      const start = new this.core.MapWeaverStart(settings);
      try {
        next = await startInSlices(start, this.trainBudget, this.buildBudget, () => generation === this.generation);
      } finally {
        start.free();
      }
      if (!next) return;
      // The first drawing of the new run's maps in a task of its own, after
      // the one that made the run (together they passed 50 ms at 1024²).
      await nextTask();
      if (generation !== this.generation) {
        next.free();
        return;
      }
      // A link may open the run part-way through: the core refuses more
      // work than its budget (naming `scans`), and the rest is done in
      // slices with the count on screen.
      if (v.scans > 0) {
        const target = next.checkFastForward(v.scans);
        if (!(await this.fastForward(next, target, generation))) {
          next.free();
          return;
        }
      }
      this.weaver?.free();
      this.weaver = next;
      caughtUp = this.catchUp(settings);
      this.readTracked();
      this.fillChoices(next.readout().choices);
      clearError(this);
    } catch (e) {
      if (next && next !== this.weaver) next.free();
      delete this.dataset.fastForward;
      showError(this, inAttributeTerms(e));
      this.status.textContent = this.weaver ? 'Kept the previous run.' : 'No run: see the message above.';
      return;
    }
    this.syncControls();
    this.makeCharts();
    this.layout();
    if (caughtUp) this.workNow();
  }

  /**
   * The settings a reader changed while `create()` made the run from
   * `made` (the old run took them, the new one was made without them) go
   * to the new run as well: no setting is lost to a rebuild. True if any did.
   */
  catchUp(made) {
    let staged = false;
    const same = (a, b) => JSON.stringify(a ?? null) === JSON.stringify(b ?? null);
    try {
      this.options.panes.forEach((o, k) => {
        const patch = Object.fromEntries(Object.entries(o).filter(([f, v]) => !same(v, made.panes[k][f])));
        if (Object.keys(patch).length > 0) {
          this.weaver.stagePane(k, patch);
          staged = true;
        }
      });
      if (this.options.person !== made.person) this.weaver.setPerson(this.options.person);
    } catch (e) {
      showError(this, inAttributeTerms(e));
    }
    return staged;
  }

  /** Advances `weaver` by `target` scans in slices, the count on screen; false when a later create() took over. */
  fastForward(weaver, target, generation) {
    return fastForward(weaver, target, this.sliceBudget, (done) => {
      this.dataset.fastForward = `${done}/${target}`;
      this.status.textContent = `Integrating the first ${count(target)} scans: ${count(done)} done…`;
    }, () => generation === this.generation).finally(() => delete this.dataset.fastForward);
  }

  /** Each pane's tracked cells, in its own image units (a pane may map at 0.05 m). */
  readTracked() {
    this.tracked = [0, 1].map((k) => this.weaver.trackedCells(k));
  }

  /** Pane `k`'s image size in cells. */
  paneSize(k) {
    const [w, h] = this.weaver.paneSize(k);
    return { w, h };
  }

  /** Gives the sliders the core's ranges and shows the knobs. */
  applyLimits() {
    const range = (s, r) => Object.assign(s.input, { min: String(r.min), max: String(r.max), step: String(r.step) });
    for (const p of this.panes) {
      range(p.clamp, this.limits.clamp);
      range(p.strength, this.limits.strength);
      range(p.beta, this.limits.betaDeg);
      p.knobs.hidden = false;
    }
  }

  /** Fills the panes' beam and cell-size menus with the run's choices (`readout().choices`). */
  fillChoices(choices) {
    this.choices = choices;
    const options = (list, label) => list.map((c) => el('option', { value: String(c.value) }, label(c.value)));
    for (const p of this.panes) {
      p.beams.input.replaceChildren(...options(choices.beams, String));
      p.resolution.input.replaceChildren(...options(choices.resolutions, (m) => `${metres(m)} m`));
    }
    this.syncControls();
  }

  /** The value the pane's menu shows for `setting`: the scene's own for none. */
  chosen(menu, setting) {
    const own = this.choices?.[menu].find((c) => c.setting === null);
    return String(setting ?? own?.value ?? '');
  }

  /** Puts the controls in line with the options. */
  syncControls() {
    if (!this.options.panes) return;
    this.personToggle.input.checked = this.options.person;
    this.situationSelect.input.value = this.values.situation;
    if (this.brierMap.on !== this.values['brier-map']) this.brierMap.set(this.values['brier-map']);
    this.speedSelect.input.value = String(this.options.speed);
    for (const p of this.panes) {
      const o = this.options.panes[p.k];
      p.learned.input.checked = o.model === 'learned';
      p.oracle.input.checked = o.pose === 'oracle';
      p.clamp.set(o.clamp);
      p.strength.set(o.strength);
      p.mapper.input.value = o.mapper;
      p.sensor.input.value = o.sensor;
      p.beta.set(o.betaDeg);
      p.beta.root.hidden = o.sensor !== 'cone';
      p.beams.input.value = this.chosen('beams', o.beams);
      p.resolution.input.value = this.chosen('resolutions', o.resolution);
      p.forget.input.checked = o.forgetL0;
    }
  }

  /** Runs `change` (a call into the core), shows an error instead of throwing, redraws. */
  knob(change) {
    if (!this.weaver) return;
    try {
      change();
      clearError(this);
    } catch (e) {
      showError(this, inAttributeTerms(e));
    }
    this.draw(true);
  }

  /**
   * Changes pane `k`'s settings (any of model, pose, clamp, strength) in
   * the options, the controls and the core.
   */
  setPane(k, patch) {
    const o = this.options.panes[k];
    Object.assign(o, patch);
    this.syncControls();
    // No run yet: the first one starts when the widget is first seen; one
    // whose settings were refused is made again from the corrected ones.
    if (!this.weaver) return void (this.started && this.create());
    // The pane is emptied now and rebuilt over the scans so far in
    // budgeted calls (the first one at once), before any new scan.
    this.knob(() => {
      this.weaver.stagePane(k, patch);
      if (REBUILD_FIELDS.some((f) => f in patch)) {
        this.readTracked();
      }
    });
    this.workNow();
  }

  setPerson(on) {
    this.options.person = on;
    this.personToggle.input.checked = on;
    this.knob(() => this.weaver.setPerson(on));
  }

  reset() {
    this.pause();
    this.stepsOwed = 0;
    this.knob(() => this.weaver.reset());
  }

  /** Step: one more scan, at once where it is small, else over the next frames. */
  step() {
    this.pause();
    this.stepsOwed += 1;
    this.workNow();
  }

  /** One call of the core's work now, the rest (if any) over the next frames. */
  workNow() {
    if (this.weaver && this.tick(0, AT_ONCE_VISITS)) this.loop.start();
  }

  play() {
    if (!this.weaver || this.playing) return;
    if (this.weaver.readout().done) this.weaver.reset();
    this.playing = true;
    this.pace.reset();
    showPlaying(this.playButton, true);
    this.status.setAttribute('aria-live', 'off');
    // The loop gets frames only while the widget is on screen.
    this.loop.start();
  }

  /**
   * One animation frame: one call of the core's work within the frame's
   * budget (at least `floor` cell visits): the scans owed for `dt` ms at
   * the chosen speed while playing, or those Step asked for, after what a
   * rebuild still lacks. False when nothing is left to do.
   */
  tick(dt, floor = 1) {
    if (!this.weaver || this.mode !== 'sim') return this.playing;
    const owed = this.playing ? this.pace.take(dt, this.options.speed * this.weaver.scanRate) : this.stepsOwed;
    // A frame that owes no scan and has no rebuild to go on with draws
    // nothing either (at speed 1 most frames owe none).
    if (owed === 0 && this.behind().every((n) => n === 0)) return this.playing;
    let r;
    try {
      r = workOnce(this.weaver, this.frameBudget, owed, floor);
      this.weaver.recordFrameMs(r.ms);
    } catch (e) {
      showError(this, e);
      this.stepsOwed = 0;
      this.pause();
      return false;
    }
    if (this.playing) this.pace.giveBack(owed - r.scans);
    else this.stepsOwed = r.done ? 0 : this.stepsOwed - r.scans;
    const more = this.stepsOwed > 0 || r.behind[0] + r.behind[1] > 0;
    // Paused, the charts catch up once the work is done (a rebuild's
    // frames redraw them no more often than playing ones).
    this.draw(!this.playing && !more);
    if (this.playing && r.done) {
      this.pause();
      return false;
    }
    return this.playing || more;
  }

  /** Stops playing; a rebuild under way goes on over the next frames. */
  pause() {
    this.loop?.stop();
    if (this.weaver && this.stepsOwed + this.behind().reduce((a, b) => a + b, 0) > 0) this.loop.start();
    if (!this.playing) return;
    this.playing = false;
    showPlaying(this.playButton, false);
    this.status.setAttribute('aria-live', 'polite');
    this.draw(true);
  }

  /** Scans each pane still lacks (a rebuild or a sweep under way). */
  behind() {
    return this.weaver.progress().behind;
  }

  // ---- drawing -----------------------------------------------------------

  /** Draws both maps, their overlays and every readout from the core's state. */
  draw(charts = false) {
    if (!this.weaver) return;
    let r;
    let behind;
    try {
      r = this.weaver.readout();
      behind = this.behind();
      r.panes.forEach((pr, k) => {
        const p = this.panes[k];
        if (!p.ctx) return;
        const { width: w, height: h } = pr;
        // The map and its layers change only with a finished scan, a new
        // size or the cursor: a frame of a sweep spread over frames, or of
        // a rebuild, leaves them as they are.
        const shown = JSON.stringify([r.scans - behind[k], pr.cellsVisited, w, p.canvas.width, p.canvas.height, this.cursor]);
        if (p.onScreen && (charts || shown !== p.shown)) {
          p.shown = shown;
          drawMapImage(p.canvas, this.memory, this.weaver.pixels(k), w, h);
          p.layers.draw({ ctx: p.ctx, s: p.cssW / w, o: { ...this.weaver.overlay(k), tracked: this.tracked[k] } });
        }
        showPaneReadout(p, pr, r, behind[k]);
      });
      const now = performance.now();
      if (charts || !this.chartTime || now - this.chartTime > CHART_EVERY_MS) {
        this.chartTime = now;
        this.drawCharts(r);
      }
      showComparison(this.comparison, r);
      this.brierMap.draw(this.weaver, this.memory, r, this.panes[0].cssW, this.limits.brierColours, charts);
      this.readCursor();
    } catch (e) {
      showError(this, e);
      this.pause();
      return;
    }
    this.dataset.scans = String(r.scans);
    this.dataset.lap = String(r.lap);
    this.dataset.done = String(r.done);
    this.dataset.situation = r.situation;
    this.reading = r;
    const frame = r.frameMs === undefined || r.frameMs === null ? '–' : fixed(r.frameMs, 2);
    this.status.textContent =
      // Parked, the robot drives no lap: the line says where it is.
      `${r.situation === 'ghost-watch' ? 'Parked in the corridor' : `Lap ${r.lap} of ${r.laps}`} · scan ${count(r.scans)} of ${count(r.totalScans)} · ${fixed(r.time, 1)} s of ${r.situation === 'ghost-watch' ? 'watching' : 'driving'} · ` +
      `core time ${frame} ms per frame${r.done ? ' · done: press Play to start again' : ''}` +
      behind.map((n, k) => (n > 0 ? ` · rebuilding the ${SIDES[k]} map: ${count(r.scans - n)} of ${count(r.scans)} scans` : '')).join('');
  }

  drawCharts(r) {
    drawCharts(this, r);
  }

  // ---- hover and keyboard cursor ----------------------------------------

  pointAt(p, e) {
    if (!this.weaver) return;
    const { w, h } = this.paneSize(p.k);
    this.cursor = { pane: p.k, ...pointerCell(p.canvas, e, w, h) };
    this.draw();
  }

  keyCursor(p, e) {
    if (!this.weaver) return;
    const c = this.cursor && this.cursor.pane === p.k ? this.cursor : this.startCell(p.k);
    const { w, h } = this.paneSize(p.k);
    const to = arrowCell(e, c, w, h);
    if (!to) return;
    e.preventDefault();
    this.cursor = { pane: p.k, ...to };
    this.draw();
  }

  /** Where the keyboard cursor starts on pane `k`: the core's first tracked cell (a wall). */
  startCell(k) {
    const t = this.tracked?.[k]?.[0];
    return { pane: k, col: t?.col ?? 0, row: t?.row ?? 0 };
  }

  /** The hover line with no cell under the pointer or the keyboard cursor. */
  clearHover() {
    this.hover.textContent = HOVER_HINT;
    this.hover.hidden = true;
    for (const k of ['l', 'p', 'updates']) delete this.hover.dataset[k];
  }

  readCursor() {
    const c = this.cursor;
    // No cell pointed at: say so, rather than keep the last cell's values.
    if (!c) return this.clearHover();
    const info = this.weaver.cellInfo(c.pane, c.col, c.row);
    if (!info) return this.clearHover();
    const side = SIDES[c.pane];
    const state = LEANINGS[info.leaning];
    this.hover.textContent =
      `${side === 'left' ? 'Left' : 'Right'} map, cell (${info.ix}, ${info.iy}) at (${fixed(info.x, 2)} m, ${fixed(info.y, 2)} m): ` +
      `l = ${signed(info.l, 3)}, p = ${fixed(info.p, 4)}, ${count(info.updates)} update${info.updates === 1 ? '' : 's'} — ${state}; ` +
      `ground truth: ${info.occupied ? 'occupied' : 'free'}.`;
    this.hover.dataset.l = String(info.l);
    this.hover.dataset.p = String(info.p);
    this.hover.dataset.updates = String(info.updates);
    placeReadout(this.hover, this.panes[c.pane].stage, c.row, this.paneSize(c.pane).h);
  }

  // ---- modes and export --------------------------------------------------

  async setMode(mode) {
    this.mode = mode;
    if (this.radios[mode]) this.radios[mode].checked = true;
    this.simPanel.hidden = mode !== 'sim';
    this.logPanel.hidden = mode !== 'log';
    if (mode !== 'log') {
      this.layout();
      // A rebuild left off in the real-log mode goes on.
      this.workNow();
      return;
    }
    this.pause();
    if (this.realLog || this.loadingLog) return;
    this.loadingLog = true;
    try {
      // The panel and the core's real-log module are fetched only now.
      const [{ RealLogPanel }, logCore] = await Promise.all([import('./map-weaver-log.js'), loadLogCore()]);
      this.realLog = new RealLogPanel(this.logPanel, logCore, this.logOptions());
      applyControls(this, this.values.controls);
    } catch (e) {
      this.logPanel.replaceChildren(el('p', { class: 'occgrid-caption map-weaver-log-missing' },
        `The real-log panel could not be loaded here (${e && e.message ? e.message : e}).`));
    } finally {
      this.loadingLog = false;
    }
  }

  /** Saves one pane's map as a ROS map_server pair (PGM + YAML, in one zip). */
  exportMap(k) {
    if (this.weaver) return exportMap(this, `apartment-${SIDES[k]}`, () => this.weaver.exportMap(k));
  }
}

/** Resolves after the page has had a frame and a task of its own. */
function nextTask() {
  return new Promise((r) => requestAnimationFrame(() => setTimeout(r, 0)));
}

if (!customElements.get('occgrid-map-weaver')) customElements.define('occgrid-map-weaver', MapWeaverElement);

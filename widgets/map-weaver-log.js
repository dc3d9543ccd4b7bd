// Map Weaver's real-log mode: a CARMEN laser log — from the file
// picker, dropped on the panel, or picked from the server's /datasets/ —
// is read and mapped a few hundred scans per call, yielding to the event
// loop between calls so the page stays responsive and a progress bar
// moves. The reader then scrubs through the build, hovers cells, changes
// the resolution and the inverse model (Table 9.2), and exports the map for
// ROS. Under dead reckoning (the log's motion increments with Table 5.6's
// noise, seeded) the dead-reckoned map is shown beside the corrected one,
// as Map Weaver's two panes are, both at one scale so that a metre is as
// long on each. One core session (RealLogSession) reads the log, holds one
// pane per pose source, integrates the scans, keeps the one state this
// panel shows (reading, awaiting-settings, building, done, failed) and
// computes every number shown, the view's scale and the keyboard cursor's
// cell included; this module lays out, forwards input, drives the session
// a slice per task and draws. The one figure measured here is the wall time
// from choosing a file to the finished map, file reading included.
//
// Usage: `new RealLogPanel(container, await loadLogCore(), { settings, log,
// limits })` (starting settings and a log of /datasets/ to load once the
// panel is first on screen, both optional, and the controls' ranges and
// menus, the chapter core's `constants().limits.realLog`); `linkState()` gives them back as they are
// now; `dispose()` frees the panel. Its control groups are marked
// `data-controls`: log-source (file picker, dataset menu), log-settings
// (resolution, the model's sliders, the pose source and its seed) and export.
import { el, slider, select, button, showError, clearError, ensureStyles, fixed, nextId, whenVisible } from './lib/ui.js';
import { exportMap, followResize } from './lib/pane.js';
import { listedLogs } from './lib/dataset-listing.js';
import { modelNote, readingCaption } from './lib/log-models.js';
import { settingsControls } from './lib/log-controls.js';
import { drawViews, dpr, paintPane } from './lib/log-view.js';
import { floatingReadout, mapStage, placeReadout } from './lib/cell-pointer.js';
import { NARROW_WIDTH, mapLegend, paneSwitcher } from './lib/log-panes.js';
import { topicChooser } from './lib/topic-chooser.js';
import { poseGraphControl } from './lib/pose-graph-layer.js';
import { statusText } from './lib/log-status.js';
import { buildPace, readPace } from './lib/build-pace.js';

const DATASET_BASE = new URL('../datasets/', import.meta.url);

/**
 * Milliseconds of core work per call before yielding: two fifths of the
 * 50 ms at which a task counts as long, leaving room for a call slower
 * than the last predicted (a SLAM build's call on the Freiburg campus ran
 * up to 2.4 times the pace of the calls before it: at 25 ms, tasks of 56
 * to 61 ms). Reads are sized in scans, builds in the core's units of work
 * (a cell update, or two cells visited: `work` in its state; a scan down
 * a corridor updates ten times the cells of one in an office), and a
 * build call also ends after the first step past its time on the page's
 * clock (`buildSlice`'s `withinMs`): in wasm a unit of SLAM's matching
 * costs two to three times a cell update's, so a budget of units learnt
 * from the maps' insertions ran long (docs/BENCHMARKS.md, W8).
 */
const SLICE_MS = 20;
/**
 * Cell updates of the first build call, before any has been timed: a few
 * milliseconds here (about 80,000 updates per millisecond), within the
 * slice on a machine several times slower. Later builds start from the
 * budget the last one reached.
 */
const FIRST_SLICE_CELLS = 250_000;
/**
 * Least time between two redraws while building, and REDRAW_SPACING times
 * the last redraw (view and side panes: 10 ms on the Intel log, 30-60 ms on
 * the campus), so that redraws take at most a ninth of a build; the counts
 * (every cell: 30 ms on the campus) wait for the finished map.
 */
const DRAW_EVERY_MS = 250;
const REDRAW_SPACING = 8;
/** Least time between two updates of the progress bar and status line. */
const PROGRESS_EVERY_MS = 100;

const count = (n) => Number(n).toLocaleString('en-US');
const READOUT_HINT = 'Point at a cell (or focus the map and use the arrow keys) to read its log odds, probability and update count.';
/** How the map canvas is operated, for its text alternative. */
const CURSOR_HINT = 'Arrow keys move a cursor cell (Shift: ten steps) whose values are read out below the map; the map follows it. + and − zoom about it, 0 shows the whole map; the mouse wheel or a pinch zooms, a drag pans.';
/** The most device pixels the map canvas gets (the core's view bound is 4,194,304). */
const MAX_VIEW_PIXELS = 4_000_000;
/** Zoom per key press, and per 100 px of wheel. */
const KEY_ZOOM = 1.5;
const WHEEL_ZOOM_PER_PX = Math.log(1.5) / 100;
/** The arrow keys' steps along the map image's columns and rows. */
const ARROWS = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };
/** The pane the reader operates (hover, zoom, cursor, export); the others are drawn whole beside it. */
const MAIN = 0;

/**
 * Yields to the event loop and comes back in a new task, after input and
 * any due frame (a `scheduler.yield()` continuation would run ahead of
 * painting: Chromium then painted only every ~110 ms during a build).
 */
const channel = new MessageChannel();
const waiting = [];
channel.port1.onmessage = () => waiting.shift()?.();
function yieldToEventLoop() {
  return new Promise((resolve) => {
    waiting.push(resolve);
    channel.port2.postMessage(null);
  });
}

/** The fields of `settings` the panel knows (the others are dropped). */
function pick(settings) {
  const out = {};
  for (const k of SETTING_FIELDS) if (settings[k] !== undefined) out[k] = settings[k];
  return out;
}

/** The settings a page may choose, as the core names them (the grid's margin stays the core's). */
export const SETTING_FIELDS = ['resolution', 'rangeCap', 'alpha', 'lOcc', 'lFree', 'clamp', 'noReturnReach', 'walls', 'poses', 'seed', 'model', 'compareModel'];

/**
 * Gives `canvas` `w × h` device pixels with its picture stretched onto
 * them: resizing a canvas clears it, and the new view is drawn in bands
 * over several tasks, so until it is whole the reader sees the old one.
 */
function resizeKeepingPicture(canvas, w, h) {
  let old = null;
  if (canvas.width > 1 && canvas.height > 1) {
    old = document.createElement('canvas');
    old.width = canvas.width;
    old.height = canvas.height;
    old.getContext('2d').drawImage(canvas, 0, 0);
  }
  canvas.width = w;
  canvas.height = h;
  if (old) {
    const ctx = canvas.getContext('2d');
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(old, 0, 0, w, h);
  }
}

export class RealLogPanel {
  /**
   * `settings`: any of SETTING_FIELDS (the core checks them when a log is
   * mapped); `log`: the file name of a log in /datasets/ to load when the
   * panel first comes into view; `limits`: the controls' ranges, names and
   * words, the chapter core's `constants().limits.realLog`.
   */
  constructor(container, { core, memory }, { settings = {}, log = null, limits }) {
    ensureStyles();
    this.core = core;
    this.limits = limits;
    this.memory = memory;
    this.session = null; // the one core session, made with the first log
    this.state = null; // the core's last state: what the panel shows
    this.geometry = null;
    this.path = null;
    this.trace = []; // each call into the core during the last load, timed, for tests
    // The settings the controls show (the core's in force once a log is mapped).
    this.settings = { ...core.RealLogSession.defaultSettings(), ...pick(settings) };
    // Poses other than the default are the reader's; else each log is mapped at its own (a bag at its odometry).
    this.posesChosen = this.settings.poses !== core.RealLogSession.defaultSettings().poses;
    this.dataset = null; // the /datasets/ log shown or read, null for a file of the reader's own
    this.fetches = 0;
    this.buildDom();
    container.append(this.root);
    this.probeDatasets();
    this.resizer = followResize(this.stage, () => this.fitCanvas());
    if (log) this.open(log);
  }

  /** The settings in force: the core's once there is a session, else those the next log is read with. */
  get applied() {
    return this.state?.settings ?? this.settings;
  }

  /** The panel's state: `{ settings, log }`, as the constructor takes them. */
  linkState() {
    const settings = {};
    for (const k of SETTING_FIELDS) settings[k] = this.settings[k];
    return { settings, log: this.dataset };
  }

  /**
   * Loads a log of /datasets/ by file name, as the menu does, once the
   * panel is on screen: a page's choice costs nothing until the reader can
   * see it (the last name asked for wins).
   */
  open(name) {
    this.wanted = name;
    if (this.waiting) return;
    this.waiting = true;
    whenVisible(this.root, () => {
      this.waiting = false;
      const wanted = this.wanted;
      this.wanted = null;
      if (wanted) this.loadUrl(wanted);
    });
  }

  /** New settings from the page (any of SETTING_FIELDS): as if the controls moved. */
  setSettings(patch) {
    this.change(pick(patch));
    this.syncControls();
  }

  /** Frees the wasm session and removes the panel. */
  dispose() {
    this.disposed = true;
    this.resizer?.disconnect();
    this.session?.free();
    this.session = null;
    this.root.remove();
  }

  buildDom() {
    const fileId = nextId('real-log-file');
    this.fileInput = el('input', { type: 'file', id: fileId, name: 'log-file', accept: '.log,.gz,.clf,.txt,.mcap,application/gzip,text/plain' });
    this.fileInput.addEventListener('change', () => {
      const file = this.fileInput.files?.[0];
      // Emptied once taken, so that choosing the same file again (after
      // another log, or to start over) is a change the input reports.
      this.fileInput.value = '';
      if (file) this.loadFile(file);
    });
    this.datasetMenu = select('Log on this server', [['', 'choose a log…']], '', (v) => v && this.loadUrl(v), { name: 'dataset' });
    this.datasetMenu.root.hidden = true;

    this.controls = settingsControls(this);
    this.topicChooser = topicChooser();

    this.progress = el('progress', { class: 'map-weaver-log-progress', max: 1, value: 0, 'aria-label': 'reading and mapping progress' });
    this.status = el('p', { class: 'map-weaver-log-status occgrid-readout', 'aria-live': 'polite' }, 'No log loaded yet.');
    this.timing = el('p', { class: 'map-weaver-log-timing occgrid-readout' });
    this.canvas = el('canvas', { class: 'occgrid-map map-weaver-log-map', role: 'img', tabindex: 0, 'aria-label': `Occupancy grid map built from the log: no log mapped yet. ${CURSOR_HINT}`, width: 1, height: 1, hidden: true });
    // Pointer events for drags and pinches, not the browser's own panning.
    this.canvas.style.touchAction = 'none';
    this.canvas.addEventListener('keydown', (e) => this.moveCursor(e));
    this.canvas.addEventListener('blur', () => { this.session?.clearCursor(MAIN); this.redraw(); this.clearCell(); });
    this.listenForViewInput();
    // A mouse left the map: its last cell would go on being read out. (A
    // lifted finger leaves at once: the tapped cell stays to be read.)
    this.canvas.addEventListener('pointerleave', (e) => { if (e.pointerType === 'mouse' && !this.cursor()) this.clearCell(); });
    this.viewStatus = el('p', { class: 'map-weaver-log-view occgrid-readout' });
    this.poseGraph = poseGraphControl(this);
    // The maps beside the operated one (the corrected map beside a
    // dead-reckoned one): drawn whole, not operated (hover, zoom, cursor,
    // scrub and export act on the first pane).
    this.mainCaption = el('figcaption', { class: 'occgrid-caption' });
    // The cell read out floats over the map too (the line below it is a screen away on a phone).
    this.readoutFloat = floatingReadout();
    this.mapStage = mapStage(this.canvas);
    this.mainPane = el('figure', { class: 'map-weaver-log-pane' }, this.mainCaption, this.mapStage);
    this.switcher = paneSwitcher(() => this.showPane());
    this.sidePanes = [];
    this.dropHint = el('p', { class: 'map-weaver-log-hint' }, 'Drop a CARMEN log (.log or .log.gz) or a ROS 2 bag (.mcap) here.');
    this.stage = el('div', { class: 'map-weaver-log-stage' }, this.mainPane, this.dropHint);
    this.sidePane(1);
    this.readout = el('p', { class: 'map-weaver-log-readout occgrid-readout', 'aria-live': 'polite' }, READOUT_HINT);
    this.counts = el('p', { class: 'map-weaver-log-counts occgrid-readout' });
    this.scrub = slider({ label: 'Scans integrated', min: 0, max: 1, step: 1, value: 0, format: (v) => `${count(v)} of ${count(this.total ?? 0)}`, onInput: (v) => this.seek(v), name: 'scrub' });
    this.scrub.input.disabled = true;
    this.exportButton = button('Export map', () => this.exportMap(), { name: 'export', title: 'Save the map as a ROS map_server PGM + YAML pair (one zip)' });
    this.exportButton.dataset.controls = 'export';
    this.exportButton.disabled = true;

    this.root = el('div', { class: 'map-weaver-log', dataset: { state: 'idle' } },
      el('div', { class: 'map-weaver-log-source occgrid-controls', role: 'group', 'aria-label': 'log to map', dataset: { controls: 'log-source' } },
        el('div', { class: 'occgrid-control' }, el('label', { for: fileId }, 'Open a CARMEN log or ROS 2 bag'), this.fileInput),
        this.datasetMenu.root),
      this.topicChooser.root,
      el('div', { class: 'occgrid-controls', role: 'group', 'aria-label': 'grid and inverse model settings', dataset: { controls: 'log-settings' } },
        Object.values(this.controls).map((c) => c.root)),
      this.progress, this.status, this.timing,
      this.switcher.root, this.stage, mapLegend(), this.poseGraph.root, this.viewStatus,
      el('div', { class: 'occgrid-controls' }, this.scrub.root, this.exportButton),
      this.readout, this.counts, modelNote(),
      readingCaption());

    const drag = (on) => (e) => {
      e.preventDefault();
      this.stage.classList.toggle('map-weaver-log-dragging', on);
    };
    this.root.addEventListener('dragenter', drag(true));
    this.root.addEventListener('dragover', drag(true));
    this.root.addEventListener('dragleave', (e) => { if (!this.root.contains(e.relatedTarget)) drag(false)(e); });
    this.root.addEventListener('drop', (e) => {
      drag(false)(e);
      const file = e.dataTransfer?.files?.[0];
      if (file) this.loadFile(file);
    });
  }

  /** The figure of pane `k` (1 and up) beside the operated map, made when first needed. */
  sidePane(k) {
    while (this.sidePanes.length < k) {
      const canvas = el('canvas', { class: 'occgrid-map map-weaver-log-reference-map', role: 'img', 'aria-label': 'The same log mapped at other poses.', width: 1, height: 1 });
      const caption = el('figcaption', { class: 'occgrid-caption' });
      const figure = el('figure', { class: 'map-weaver-log-reference', hidden: true }, caption, canvas);
      this.stage.insertBefore(figure, this.dropHint);
      this.sidePanes.push({ figure, caption, canvas, geometry: null, path: null });
    }
    return this.sidePanes[k - 1];
  }

  loadFile(file) {
    this.dataset = null;
    this.showDataset();
    return this.load(file.name, async () => new Uint8Array(await file.arrayBuffer()));
  }

  loadUrl(name) {
    this.dataset = name;
    this.showDataset();
    // The file picker would otherwise go on naming the reader's last file.
    this.fileInput.value = '';
    return this.load(name, async () => {
      const response = await fetch(new URL(name, DATASET_BASE));
      if (!response.ok) throw new Error(`cannot fetch ${name}: HTTP ${response.status}`);
      return new Uint8Array(await response.arrayBuffer());
    });
  }

  /**
   * Hands a log's bytes to the session (the first log makes it) and drives
   * it: the core reads and maps, the panel shows its state. Timed from the
   * reader's choice, file reading included.
   */
  async load(name, getBytes, topics = null) {
    const t0 = performance.now();
    const ticket = ++this.fetches;
    clearError(this.root);
    this.topicChooser.hide();
    this.timing.textContent = '';
    this.trace = [];
    let bytes;
    try {
      bytes = await getBytes();
    } catch (e) {
      return void showError(this.root, e, `${name}: `);
    }
    // Another log was chosen meanwhile: it wins.
    if (ticket !== this.fetches || this.disposed) return;
    this.trace.push(['file', performance.now() - t0]);
    const t = performance.now();
    const first = !this.session;
    try {
      if (this.session) this.session.open(bytes, name);
      else this.session = new this.core.RealLogSession(bytes, name);
      if (topics) this.session.chooseTopics(topics.scan, topics.odom);
    } catch (e) {
      return void showError(this.root, e, `${name}: `);
    }
    const own = this.posesChosen ? null : this.session.ownPoses();
    if (own && own !== this.settings.poses) { this.settings = { ...this.settings, poses: own }; this.syncControls(); if (!first) this.applySettings(); }
    // The first log makes the session: it takes the panel's settings.
    if (first) this.applySettings();
    this.trace.push(['copy', performance.now() - t]);
    this.reading = name;
    this.opened = { name, bytes }; // kept until read, for a bag's topic choice
    this.job = { kind: 'load', name, t0 };
    // A first call of 32 scans: a bag's reach its first chunk (about 36
    // Intel scans to a 40 KB zstd chunk, 3-10 ms in wasm); later calls are
    // sized from the scans each call reports, at the pace of the read's
    // slowest call (readPace).
    this.readBudget = 32;
    this.readPace = readPace(SLICE_MS);
    this.show(this.session.state());
    this.drive();
  }

  /**
   * Drives the session while its state is `reading` or `building`: one
   * call into the core per task (a read of a budget of scans, a build
   * slice of a budget of work, or a band of a drawing), each budget sized
   * from the calls before it (readPace, buildPace). One loop at a time: new settings, a
   * scrub or another log change the session, and the loop follows it.
   */
  async drive() {
    if (this.driving) return;
    this.driving = true;
    try {
      let drawn = performance.now();
      let msPerScan = 0;
      // Setting the map up (reading's last call, or new settings) had a task of its own.
      await this.pause();
      while (!this.disposed && this.session) {
        const s = this.state;
        if (this.drawPending) {
          [this.drawPending, this.drawingLater] = [false, true];
          const whole = await drawViews(this, false);
          this.drawingLater = false;
          // A panel is done once its maps are drawn.
          if (!this.drawPending && this.state) this.root.dataset.state = this.state.state;
          if (!whole) break;
        } else if (s.state === 'reading' || s.state === 'planning') {
          this.readStep(s.state === 'planning');
        } else if (s.state === 'building') {
          const last = s.panes[MAIN];
          const t = performance.now();
          const cells = this.sliceCells ?? FIRST_SLICE_CELLS;
          let next;
          try {
            next = this.session.buildSlice(cells, SLICE_MS);
          } catch (e) {
            // A map passed its tile budget (the core says how much the log
            // needs): the maps so far stay on screen.
            this.show(this.session.state());
            showError(this.root, e, 'map: ');
            this.drawLater();
            break;
          }
          const ms = performance.now() - t;
          const did = next.work - s.work;
          this.trace.push(['build', ms, cells, did, next.scansDone]);
          // A rebuild restarted the count: no duration to learn from.
          if (did > 0) this.sliceCells = (this.buildPace ??= buildPace(SLICE_MS)).next(cells, ms, did);
          msPerScan = ms / Math.max(1, next.panes[MAIN].scansDone - last.scansDone);
          const remaining = (next.scansTarget - next.scansDone) * msPerScan;
          if (next.finished || (performance.now() - drawn > Math.max(DRAW_EVERY_MS, REDRAW_SPACING * (this.redrawMs ?? 0)) && remaining > DRAW_EVERY_MS)) {
            // The panel shows a finished state once it has drawn it.
            if (next.finished) this.state = next;
            else this.show(next, this.progressDue());
            if (!(await drawViews(this, next.finished))) break;
            drawn = performance.now();
            // The session may have moved on meanwhile (new settings, a scrub): show where it is now.
            if (next.finished) this.show(this.session.state());
            if (this.state.state === 'done') this.finishJob(this.state);
          } else {
            this.show(next, this.progressDue());
          }
        } else {
          break;
        }
        await this.pause();
      }
    } finally {
      this.driving = false;
      // A drawing asked for as the loop ended (a refused build) still gets its loop.
      if (this.drawPending && !this.disposed && this.session) this.drive();
    }
  }

  /** One read call (or, after new settings, `planning` one) of a budget of scans sized from the last, and what it brings. */
  readStep(planning = false) {
    const t = performance.now();
    const n = this.readBudget;
    let report;
    try {
      report = planning ? this.session.plan(n) : this.session.read(n);
    } catch (e) {
      const state = this.session.state();
      this.show(state);
      // Settings that make no map of the log: the ones in force stay, and the controls show them.
      if (planning) { this.settings = pick(state.settings); this.job = null; this.syncControls(); }
      showError(this.root, e, planning ? 'settings: ' : `${this.reading}: `);
      const { name, bytes } = this.opened ?? {};
      if (state.topics && bytes) this.topicChooser.show(state.topics, (choice) => this.load(name, async () => bytes, choice));
      if (state.state === 'awaiting-settings') this.layout();
      return;
    }
    const ms = performance.now() - t;
    this.trace.push([planning ? 'plan' : 'read', ms, n, report.work]);
    // Sized by the work done (scans read, or walked to plan the panes).
    this.readBudget = (this.readPace ??= readPace(SLICE_MS)).next(n, ms, Math.max(1, report.work));
    // The read log's own poses, unless the reader chose: a bag's corrected ones when its read found a map → odom transform.
    const own = report.finished && !this.posesChosen ? this.session.ownPoses() : null;
    if (own && own !== this.settings.poses) { this.settings = { ...this.settings, poses: own }; this.syncControls(); this.applySettings(); }
    const state = this.session.state();
    if (report.finished) {
      // The whole log is read and its panes set up: the maps are this log's.
      this.name = this.reading;
      this.opened = null;
      if (this.job) this.job.readMs = performance.now() - this.job.t0;
      this.layout();
    }
    this.show(state, report.finished || this.progressDue());
  }

  /** Every pane's view drawn again in bands (a new size, new settings, a rebuild shown at once) by the loop that drives the session, between its calls. */
  drawLater() {
    this.drawPending = true;
    this.drive();
  }

  /** The load or rebuild that just finished: its time on the page. */
  finishJob(state) {
    const job = this.job;
    this.job = null;
    this.rereadCell();
    if (!job) return;
    const ms = performance.now() - job.t0;
    if (job.kind === 'load') {
      const read = state.read;
      this.root.dataset.totalMs = ms.toFixed(1);
      this.root.dataset.readMs = (job.readMs ?? ms).toFixed(1);
      // A log cut short is mapped up to the cut; say where it was cut.
      const warning = read?.warning ? ` Warning: ${read.warning}.` : '';
      this.timing.textContent =
        `${job.name}: ${count(read?.records ?? 0)} ${read?.recordName ?? 'records'} (${count(Math.round((read?.bytesTotal ?? 0) / 1024))} kB) read and ${count(state.panes[MAIN].scansDone)} scans mapped ` +
        `in ${count(Math.round(ms))} ms, file reading included (reading ${count(Math.round(job.readMs ?? ms))} ms).${warning}`;
    } else if (job.kind === 'rebuild') {
      this.timing.textContent =
        `Rebuilt with the new settings (${state.settings.resolution} m cells): ${count(state.panes[MAIN].scansDone)} scans mapped in ${count(Math.round(ms))} ms.`;
    }
  }

  /** Shows the core's state: `data-state` is the session's; with `full`, the progress, status and controls too. */
  show(state, full = true) {
    this.state = state;
    // A panel is done once its maps are drawn (drive says so after drawLater's drawing).
    this.root.dataset.state = state.state === 'done' && (this.drawPending || this.drawingLater) ? 'drawing' : state.state;
    this.root.setAttribute('aria-busy', String(/^(reading|planning|building)$/.test(state.state)));
    if (!full) return;
    this.progress.value = state.progress;
    const main = state.panes[MAIN];
    const text = statusText(state, this.reading ?? this.name);
    if (text !== null) this.status.textContent = text;
    if (main && (state.state === 'building' || state.state === 'done')) this.scrub.set(main.scansDone);
    // The maps can be scrubbed whenever there are maps, but not while a log
    // is read; exported only once built to the scan chosen (never a map cut
    // short by its budget, or half built).
    const mapped = state.panes.length > 0 && !!this.geometry;
    this.scrub.input.disabled = !mapped || state.state === 'reading';
    this.exportButton.disabled = !mapped || state.state !== 'done';
    // The range cap's slider ends where the core's limit at the resolution
    // in force does (or at the value in force, if a log waits for settings).
    const max = String(Math.max(Math.floor(state.limits.rangeCapMax), Math.ceil(state.settings.rangeCap)));
    if (this.controls.rangeCap.input.max !== max) this.controls.rangeCap.input.max = max;
  }

  /** Shows the dataset menu when the server has /datasets/ beside /widgets/: the logs its README's table lists, by name. */
  async probeDatasets() {
    let logs = [];
    try {
      const r = await fetch(new URL('README.md', DATASET_BASE));
      if (r.ok) logs = listedLogs(await r.text());
    } catch {
      // Not served here: the menu stays hidden.
    }
    const input = this.datasetMenu.input;
    input.replaceChildren(el('option', { value: '' }, 'choose a log…'), ...logs.map(([n, label]) => el('option', { value: n }, label)));
    this.datasetMenu.root.hidden = logs.length === 0;
    // The listing is decided (its fetch answered or failed): the logs it offers.
    input.dataset.listed = String(logs.length);
    this.showDataset();
  }

  /** The menu shows the /datasets/ log in the panel (or none). */
  showDataset() {
    const input = this.datasetMenu.input;
    const listed = [...input.options].some((o) => o.value === this.dataset);
    input.value = listed ? this.dataset : '';
  }

  /** Canvas device pixels of a pointer event (inside the canvas's border). */
  viewPoint(e) {
    const c = this.canvas;
    const rect = c.getBoundingClientRect();
    return {
      x: ((e.clientX - rect.left - c.clientLeft) / Math.max(1, c.clientWidth)) * c.width,
      y: ((e.clientY - rect.top - c.clientTop) / Math.max(1, c.clientHeight)) * c.height,
    };
  }

  /** Wheel zoom, one-finger (or mouse) drag to pan, two-finger pinch to zoom, hover readout. */
  listenForViewInput() {
    const pointers = new Map();
    let last = null;
    const pinch = () => {
      const [a, b] = [...pointers.values()];
      return { x: (a.x + b.x) / 2, y: (a.y + b.y) / 2, d: Math.hypot(a.x - b.x, a.y - b.y) };
    };
    this.canvas.addEventListener('wheel', (e) => {
      if (!this.view) return;
      e.preventDefault();
      const px = e.deltaMode === 1 ? 16 : e.deltaMode === 2 ? 400 : 1;
      const { x, y } = this.viewPoint(e);
      this.session.zoomAt(MAIN, x, y, Math.exp(-e.deltaY * px * WHEEL_ZOOM_PER_PX));
      this.renderView();
      this.readViewCell(x, y);
    }, { passive: false });
    this.canvas.addEventListener('pointerdown', (e) => {
      if (!this.view) return;
      this.canvas.setPointerCapture?.(e.pointerId);
      const p = this.viewPoint(e);
      pointers.set(e.pointerId, p);
      last = pointers.size === 2 ? pinch() : null;
      // A tap fires no move: the press reads the cell under it.
      if (pointers.size === 1) this.readViewCell(p.x, p.y);
    });
    const release = (e) => {
      pointers.delete(e.pointerId);
      last = pointers.size === 2 ? pinch() : null;
    };
    this.canvas.addEventListener('pointerup', release);
    this.canvas.addEventListener('pointercancel', release);
    this.canvas.addEventListener('pointermove', (e) => {
      if (!this.view) return;
      const p = this.viewPoint(e);
      const before = pointers.get(e.pointerId);
      if (!before) {
        if (this.cursor()) {
          this.session.clearCursor(MAIN);
          this.redraw();
        }
        this.readViewCell(p.x, p.y);
        return;
      }
      pointers.set(e.pointerId, p);
      if (pointers.size === 1) {
        this.session.panBy(MAIN, p.x - before.x, p.y - before.y);
      } else if (pointers.size === 2) {
        const now = pinch();
        if (last && last.d > 0) {
          this.session.panBy(MAIN, now.x - last.x, now.y - last.y);
          this.session.zoomAt(MAIN, now.x, now.y, now.d / last.d);
        }
        last = now;
      }
      this.renderView();
    });
  }

  /** True at most every PROGRESS_EVERY_MS: a changed status costs a paint of the page. */
  progressDue() {
    const now = performance.now();
    if (this.shownAt !== undefined && now - this.shownAt < PROGRESS_EVERY_MS) return false;
    this.shownAt = now;
    return true;
  }

  /** Ends the task: the next core call runs in a new one (the trace marks it for tests). */
  pause() {
    this.trace.push(['yield']);
    return yieldToEventLoop();
  }

  /** After a read or new settings: the panes' limits, captions and paths from the core, and the canvases sized for them. */
  layout() {
    const panes = this.session?.state().panes ?? [];
    this.geometry = panes.length ? this.session.geometry(MAIN) : null;
    // The last image belongs to the old geometry (or the old log), and so
    // does the last cell read out.
    this.pixels = null;
    this.clearCell();
    if (panes.length > 1) this.sidePane(panes.length - 1);
    this.sidePanes.forEach((side, i) => {
      const k = i + 1;
      const shown = k < panes.length;
      side.figure.hidden = !shown;
      side.geometry = shown ? this.session.geometry(k) : null;
      side.path = shown ? this.session.pathPixels(k) : null;
      if (shown) side.caption.textContent = panes[k].caption;
    });
    this.mainCaption.hidden = panes.length < 2;
    if (panes.length > 1) this.mainCaption.textContent = panes[MAIN].caption;
    if (!this.geometry) {
      this.canvas.hidden = true;
      this.path = null;
      return;
    }
    this.canvas.hidden = false;
    this.path = this.session.pathPixels(MAIN);
    this.total = panes[MAIN].scansTotal;
    this.scrub.input.max = String(this.total);
    this.fitCanvas();
  }

  /**
   * Display size: the whole map's shape within the panel's width and 75% of
   * the window's height; the canvas has the display's device pixels
   * (bounded), into which the core draws only the part of the map in view.
   * Beside other panes, each gets its share of the width, all at the same
   * CSS pixels per cell (one log, one resolution: one scale).
   */
  fitCanvas() {
    if (!this.geometry || !this.session) return;
    const panes = [[this.canvas, this.geometry, MAIN]];
    this.sidePanes.forEach((side, i) => {
      if (side.geometry && !side.figure.hidden) panes.push([side.canvas, side.geometry, i + 1]);
    });
    const narrow = panes.length > 1 && this.stage.clientWidth < NARROW_WIDTH;
    this.switcher.update(panes.map(([, , k]) => (k === MAIN ? this.mainCaption : this.sidePanes[k - 1].caption).textContent), narrow);
    this.stage.classList.toggle('map-weaver-log-narrow', narrow);
    this.showPane();
    const avail = Math.max(100, (this.stage.clientWidth - 8) / (narrow ? 1 : panes.length) - (panes.length > 1 && !narrow ? 8 : 0));
    const fit = Math.min(...panes.map(([, g]) => Math.min(avail / g.width, (0.75 * window.innerHeight) / g.height)));
    for (const [canvas, { width, height }, k] of panes) {
      const cssW = Math.max(1, Math.floor(width * fit));
      const cssH = Math.max(1, Math.floor(height * fit));
      const scale = Math.min(window.devicePixelRatio || 1, Math.sqrt(MAX_VIEW_PIXELS / (cssW * cssH)));
      const w = Math.max(1, Math.round(cssW * scale));
      const h = Math.max(1, Math.round(cssH * scale));
      canvas.style.width = `${Math.floor(cssW)}px`;
      canvas.style.height = `${Math.floor(cssH)}px`;
      if (canvas.width !== w || canvas.height !== h) resizeKeepingPicture(canvas, w, h);
      this.session.setViewSize(k, w, h);
    }
    this.stage.classList.toggle('map-weaver-log-comparing', panes.length > 1);
    this.drawLater();
  }

  /** On a narrow screen, the map the switcher names is the one displayed. */
  showPane() {
    [this.mainPane, ...this.sidePanes.map((s) => s.figure)].forEach((f, k) => f.classList.toggle('map-weaver-log-shown', k === this.switcher.shown));
  }

  /** The operated map's figures in the status line, counts and label, after drawing it (unless `render` is false: drawn already). */
  draw(render = true) {
    const p = this.state.panes[MAIN];
    if (render) this.renderView();
    const { width, height, resolution } = this.geometry;
    const c = this.session.counts(MAIN);
    if (p.finished) {
      this.status.textContent =
        `${count(p.scansDone)} of ${count(p.scansTotal)} scans, ${count(p.beams)} beams, ${count(p.cellUpdates)} cell updates · ` +
        `map ${count(width)} × ${count(height)} cells at ${resolution} m${p.loopClosures == null ? '' : ` · ${count(p.loopClosures)} loop closures`}`;
    }
    // The thresholds are the exported YAML's (the core sends them with the
    // counts): the figures are what map_server would load from the file.
    const occ = `p > ${c.occupiedThresh}`;
    const free = `p < ${c.freeThresh}`;
    this.counts.textContent =
      `as exported: occupied (${occ}) ${count(c.occupied)} · free (${free}) ${count(c.free)} · unknown ${count(c.unknown)} of ${count(c.cells)} cells`;
    Object.assign(this.root.dataset, {
      scans: String(p.scansDone), occupied: String(c.occupied), free: String(c.free), unknown: String(c.unknown), cells: String(c.cells),
      cellsAllocated: String(p.cellsAllocated),
    });
    this.canvas.setAttribute('aria-label',
      `Occupancy grid map of ${this.name}, ${count(width)} × ${count(height)} cells of ${resolution} m, ` +
      `after ${count(p.scansDone)} of ${count(p.scansTotal)} scans: ${count(c.occupied)} cells occupied (${occ}), ${count(c.free)} free (${free}), ` +
      `${count(c.unknown)} unknown. Gray is unknown, white free, black occupied; the green line is the laser’s path. ${CURSOR_HINT}`);
  }

  /** Draws the view of the operated map the core holds (no map-sized image: the view's pixels only) and states its scale. */
  renderView() {
    if (!this.session || !this.geometry) return;
    this.session.renderView(MAIN);
    this.showView();
  }

  /** Shows the operated map's last whole view (no core drawing), and states its scale. */
  showView() {
    this.pixels = this.session.viewPixels(MAIN);
    this.view = this.session.view(MAIN);
    this.redraw();
    const v = this.view;
    const legend = this.session.viewLegend(MAIN, dpr(this.canvas));
    this.viewStatus.textContent = `view: ${legend.text} · wheel or pinch to zoom, drag to pan, + − 0 and arrows on the focused map`;
    Object.assign(this.root.dataset, { viewScale: String(v.scale), viewWidth: String(v.width), viewHeight: String(v.height) });
  }

  /** The operated map from its last rendered view (no core drawing). */
  redraw() {
    if (!this.pixels || !this.view) return;
    paintPane(this, this.canvas, MAIN, this.pixels, this.view, this.path, this.cursor());
  }

  /** Pane `k` beside the operated one, from its last whole view, with its path and robot. */
  paintSide(k) {
    const side = this.sidePanes[k - 1];
    if (!this.session || !side?.geometry || side.figure.hidden) return;
    paintPane(this, side.canvas, k, this.session.viewPixels(k), this.session.view(k), side.path);
  }

  /** The operated map's keyboard cursor `{ col, row }` (the core's), or null. */
  cursor() {
    return this.session && this.geometry ? this.session.cursor(MAIN) : null;
  }

  /** Arrow keys move the core's cursor (Shift: ten steps; the view follows it), + and - zoom about it, 0 fits the map. */
  moveCursor(e) {
    if (!this.geometry || !this.view) return;
    let cell;
    if (e.key === '+' || e.key === '=' || e.key === '-' || e.key === '_') {
      cell = this.session.zoomAtCursor(MAIN, e.key === '+' || e.key === '=' ? KEY_ZOOM : 1 / KEY_ZOOM);
    } else if (e.key === '0') {
      cell = this.session.fitView(MAIN);
    } else if (ARROWS[e.key]) {
      const [dx, dy] = ARROWS[e.key];
      cell = this.session.moveCursor(MAIN, dx, dy, e.shiftKey);
    } else {
      return;
    }
    e.preventDefault();
    this.renderView();
    if (cell) this.showReadout(cell);
  }

  /** Reads out the cell under canvas pixel `(x, y)` of the view. */
  readViewCell(x, y) {
    const c = this.session?.cellAtView(MAIN, x, y);
    if (c) this.showReadout(c, y);
  }

  /** Reads out cell `c`, over the map too, clear of canvas row `y` (device pixels; the cursor's row when absent). */
  showReadout(c, y = null) {
    for (const k of ['x', 'y', 'ix', 'iy', 'l', 'p', 'updates']) this.readout.dataset[k] = String(c[k]);
    this.readout.textContent =
      `cell (${c.ix}, ${c.iy}) at (${fixed(c.x, 2)} m, ${fixed(c.y, 2)} m): l = ${fixed(c.l, 3)}, p = ${fixed(c.p, 3)}, ` +
      `${count(c.updates)} update${c.updates === 1 ? '' : 's'}`;
    this.readoutFloat.textContent = this.readout.textContent;
    const at = y ?? this.cursorY();
    placeReadout(this.readoutFloat, this.mapStage, at, this.canvas.height);
  }

  /** The keyboard cursor's row on the canvas, device pixels (the canvas's middle without one). */
  cursorY() {
    const at = this.cursor();
    const v = this.view;
    return at && v ? (at.row + 0.5 - v.v0) * v.scale : this.canvas.height / 2;
  }

  /** The cell readout with no cell pointed at (its values would be stale). */
  clearCell() {
    this.readout.textContent = READOUT_HINT;
    this.readoutFloat.hidden = true;
    for (const k of ['x', 'y', 'ix', 'iy', 'l', 'p', 'updates']) delete this.readout.dataset[k];
  }

  /** After a rebuild or a scrub: the keyboard cursor's cell read again, else no cell. */
  rereadCell() {
    const at = this.cursor();
    const c = at && this.session.cellAt(MAIN, at.col, at.row);
    if (c) this.showReadout(c);
    else this.clearCell();
  }

  /** A control moved: the core takes the settings at once (or refuses them by name), and its state is the rebuild's from then on. */
  change(patch) {
    if ('poses' in patch) this.posesChosen = true;
    this.settings = { ...this.settings, ...patch };
    if (!this.session) return;
    const before = this.state?.panes.length ? this.geometry : null;
    if (!this.applySettings()) return;
    const state = this.session.state();
    const planning = state.state === 'planning'; // the maps on screen stay until the new ones are planned
    if (state.panes.length === 0 && !planning) return void this.show(state);
    // The load's timing line was for the settings it was mapped with.
    if (before || this.job?.kind !== 'load') this.job = { kind: 'rebuild', t0: performance.now() };
    this.timing.textContent = '';
    if (!planning) this.layout();
    this.follow(state);
  }

  /** Shows the state after a change of the maps: drawn at once if there is nothing to build (a scrub to where the maps are), else built. */
  follow(state) {
    if (state.state === 'done') this.drawLater();
    this.show(state);
    if (state.state !== 'done') return void this.drive();
    this.draw(false);
    this.finishJob(state);
  }

  /** Hands the controls' settings to the core: true if it took them, else the controls go back to the settings in force. */
  applySettings() {
    try {
      this.session.configure(this.settings);
      clearError(this.root);
      return true;
    } catch (e) {
      showError(this.root, e, 'settings: ');
      this.settings = pick(this.session.state().settings);
      this.syncControls();
      return false;
    }
  }

  syncControls() {
    const s = this.settings;
    this.controls.resolution.input.value = String(s.resolution);
    this.controls.walls.input.value = String(s.walls);
    this.controls.poses.input.value = String(s.poses);
    this.controls.seed.input.value = String(s.seed);
    for (const key of ['rangeCap', 'alpha', 'lOcc', 'lFree', 'clamp', 'noReturnReach', 'model', 'compareModel']) this.controls[key].set(s[key]);
  }

  async seek(k) {
    if (!this.session || !this.geometry) return;
    try {
      this.session.seek(k);
    } catch (e) {
      return void showError(this.root, e, 'scrub: ');
    }
    this.job = null;
    this.clearCell();
    this.follow(this.session.state());
  }

  exportMap() {
    if (!this.session || !this.geometry) return;
    const stem = this.session.exportStem(MAIN, this.name);
    return exportMap(this.root, stem, () => this.session.exportMap(MAIN, stem, this.name), 'export: ');
  }
}

// Map Weaver's real-log mode (SPEC §11): a CARMEN laser log — from the file
// picker, dropped on the panel, or picked from the server's /datasets/ —
// is read and mapped a few hundred scans per call, yielding to the event
// loop between calls so the page stays responsive and a progress bar
// moves. The reader then scrubs through the build, hovers cells, changes
// the resolution and the inverse model (Table 9.2), and exports the map for
// ROS. Under dead reckoning (the log's motion increments with Table 5.6's
// noise, seeded) the dead-reckoned map is shown beside the corrected one,
// as Map Weaver's two panes are, both at one scale so that a metre is as
// long on each. The core (LogMapSession) parses the log, finds the grid's extent,
// integrates the scans and computes every number shown; this module lays
// out, forwards input and draws. The one figure measured here is the wall
// time from choosing a file to the finished map, file reading included.
//
// Usage: `new RealLogPanel(container, await loadCore(), { settings, log })`
// (both optional: starting settings, and a log of /datasets/ to load once
// the panel is first on screen); `linkState()` gives them back as they are
// now; `dispose()` frees the panel. Its control groups are marked
// `data-controls`: log-source (file picker, dataset menu), log-settings
// (resolution, the model's sliders, the pose source and its seed) and export.
import { el, slider, select, button, showError, clearError, ensureStyles, fixed, nextId, whenVisible } from './lib/ui.js';
import { arrowCell, exportMap, followResize } from './lib/pane.js';
import { drawMapImage, drawPath, drawRobot, outlineCell } from './lib/layers.js';

/** Descriptions of the logs the project's /datasets/ holds. */
const DATASETS = [
  ['intel-corrected.log.gz', 'Intel Research Lab, Seattle (910 scans)'],
  ['aces-corrected.log.gz', 'ACES building, UT Austin (440 scans)'],
];
const DATASET_BASE = new URL('../datasets/', import.meta.url);

/**
 * Milliseconds of core work per call before yielding to the event loop:
 * half the 50 ms at which a task counts as long (and input starts to feel
 * late), leaving room for a call that runs slower than the last one
 * predicted, and long enough that the cost of each yield stays small.
 * Reads are sized in scans, builds in cell updates (`buildSlice`): a scan
 * down a corridor updates ten times the cells of one in an office, so a
 * count of scans could not keep a build's calls near the slice.
 */
const SLICE_MS = 25;
/**
 * Cell updates of the first build call, before any has been timed: a few
 * milliseconds here (about 80,000 updates per millisecond), so that a
 * machine several times slower still stays within the slice, while a short
 * build is not spent in tiny calls (each yield may wait for a frame). Later
 * builds start from the budget the last one reached.
 */
const FIRST_SLICE_CELLS = 250_000;
/**
 * Least time between two redraws of the map while it is being built (the
 * first after as long): redrawing a million-cell map costs 10 to 40 ms, so
 * a short build (the Intel log) is drawn once, when done, and a long one a
 * few times a second.
 */
const DRAW_EVERY_MS = 250;
/** Least time between two updates of the progress bar and status line. */
const PROGRESS_EVERY_MS = 100;
/** Share of the progress bar for reading the file; the rest is mapping. */
const READ_SHARE = 0.3;
const PATH_COLOR = 'rgba(26, 152, 80, 0.55)';
const ROBOT_COLOR = '#1a9850';
const CURSOR_COLOR = '#2c7bb6';

const count = (n) => Number(n).toLocaleString('en-US');
const READOUT_HINT = 'Point at a cell (or focus the map and use the arrow keys) to read its log odds, probability and update count.';
/** How the map canvas is operated, for its text alternative. */
const CURSOR_HINT = 'Arrow keys move a cursor cell (Shift: ten steps) whose values are read out below the map; the map follows it. + and − zoom about it, 0 shows the whole map; the mouse wheel or a pinch zooms, a drag pans.';
/** The most device pixels the map canvas gets (the core's view bound is 4,194,304). */
const MAX_VIEW_PIXELS = 4_000_000;
/** Zoom per key press, and per 100 px of wheel. */
const KEY_ZOOM = 1.5;
const WHEEL_ZOOM_PER_PX = Math.log(1.5) / 100;
/** Device pixels a cursor step moves at any zoom (at least one cell). */
const CURSOR_STEP_PX = 16;

/**
 * Yields to the event loop and comes back in a new task: input is handled
 * and, when a frame is due, the progress bar and map are painted. (A
 * `scheduler.yield()` continuation would run ahead of painting: Chromium
 * then painted only every ~110 ms during a build.)
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

/**
 * The next call's budget: the work the last call did (`done`, in its units)
 * scaled to SLICE_MS by the last call's duration, and at most twice the last
 * budget `n`.
 */
export function nextChunk(n, ms, done = n) {
  return Math.max(1, Math.min(n * 2, Math.round((done * SLICE_MS) / Math.max(ms, 0.25))));
}

/** The fields of `settings` the panel knows (the others are dropped). */
function pick(settings) {
  const out = {};
  for (const k of SETTING_FIELDS) if (settings[k] !== undefined) out[k] = settings[k];
  return out;
}

/** "intel-corrected.log.gz" → "intel-corrected-map" */
function mapStem(fileName) {
  return `${fileName.replace(/\.gz$/i, '').replace(/\.(log|clf|txt)$/i, '') || 'log'}-map`;
}

/** The settings a page may choose, as the core names them (the grid's margin stays the core's). */
export const SETTING_FIELDS = ['resolution', 'rangeCap', 'alpha', 'lOcc', 'lFree', 'clamp', 'noReturnReach', 'walls', 'poses', 'seed'];
/** What the seed field accepts (the core's MAX_SEED: a JavaScript number's whole range). */
const SEED_TEXT = /^\d{1,16}$/;

export class RealLogPanel {
  /**
   * `settings`: any of SETTING_FIELDS (the core checks them when a log is
   * mapped); `log`: the file name of a log in /datasets/ to load when the
   * panel first comes into view.
   */
  constructor(container, { core, memory }, { settings = {}, log = null } = {}) {
    ensureStyles();
    this.core = core;
    this.memory = memory;
    this.session = null;
    this.geometry = null;
    this.path = null;
    this.run = 0;
    /** Duration of each call into the core during the last load, for tests. */
    this.trace = [];
    this.settings = { ...core.LogMapSession.defaultSettings(), ...pick(settings) };
    this.applied = { ...this.settings };
    /** The /datasets/ log shown (or being read), null for a file of the reader's own. */
    this.dataset = null;
    this.buildDom();
    container.append(this.root);
    this.probeDatasets();
    this.resizer = followResize(this.stage, () => this.fitCanvas());
    if (log) this.open(log);
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
    this.run++;
    this.resizer?.disconnect();
    this.session?.free();
    this.session = null;
    this.reference?.free();
    this.reference = null;
    this.root.remove();
  }

  buildDom() {
    const fileId = nextId('real-log-file');
    this.fileInput = el('input', { type: 'file', id: fileId, name: 'log-file', accept: '.log,.gz,.clf,.txt,application/gzip,text/plain' });
    this.fileInput.addEventListener('change', () => {
      const file = this.fileInput.files?.[0];
      if (file) this.loadFile(file);
    });
    this.datasetMenu = select('Log on this server', [['', 'choose a log…']], '', (v) => v && this.loadUrl(v), { name: 'dataset' });
    this.datasetMenu.root.hidden = true;

    const s = this.settings;
    const m = (v) => `${fixed(v, 2)} m`;
    this.controls = {
      resolution: select('Resolution', [['0.025', '2.5 cm'], ['0.05', '5 cm'], ['0.1', '10 cm'], ['0.2', '20 cm']], String(s.resolution), (v) => this.change({ resolution: Number(v) }), { name: 'resolution' }),
      rangeCap: slider({ label: 'z_max (range cap)', min: 2, max: 80, step: 1, value: s.rangeCap, format: (v) => `${v} m`, onInput: (v) => this.change({ rangeCap: v }), name: 'range-cap' }),
      alpha: slider({ label: 'α (obstacle depth)', min: 0.02, max: 0.5, step: 0.01, value: s.alpha, format: m, onInput: (v) => this.change({ alpha: v }), name: 'alpha' }),
      lOcc: slider({ label: 'l_occ', min: 0.05, max: 3, step: 0.05, value: s.lOcc, format: (v) => fixed(v, 2), onInput: (v) => this.change({ lOcc: v }), name: 'l-occ' }),
      lFree: slider({ label: 'l_free', min: -3, max: -0.05, step: 0.05, value: s.lFree, format: (v) => fixed(v, 2), onInput: (v) => this.change({ lFree: v }), name: 'l-free' }),
      clamp: slider({ label: 'clamp l_max', min: 0.5, max: 12, step: 0.5, value: s.clamp, format: (v) => fixed(v, 1), onInput: (v) => this.change({ clamp: v }), name: 'clamp' }),
      noReturnReach: slider({ label: 'no-return reach', min: 1, max: 80, step: 1, value: s.noReturnReach, format: (v) => `${v} m`, onInput: (v) => this.change({ noReturnReach: v }), name: 'no-return-reach' }),
      walls: select('Free evidence near walls', [['incidence', 'stops at the wall a beam grazes'], ['table-9.2', 'Table 9.2 (walls wear away)']], s.walls, (v) => this.change({ walls: v }), { name: 'walls' }),
      poses: select('Poses', [['corrected', 'corrected (the log’s)'], ['dead-reckoning', 'dead reckoning (Table 5.6 noise)']], s.poses, (v) => this.change({ poses: v }), { name: 'poses' }),
      seed: this.seedControl(s.seed),
    };

    this.progress = el('progress', { class: 'map-weaver-log-progress', max: 1, value: 0, 'aria-label': 'reading and mapping progress' });
    this.status = el('p', { class: 'map-weaver-log-status occgrid-readout', 'aria-live': 'polite' }, 'No log loaded yet.');
    this.timing = el('p', { class: 'map-weaver-log-timing occgrid-readout' });
    this.canvas = el('canvas', { class: 'occgrid-map map-weaver-log-map', role: 'img', tabindex: 0, 'aria-label': `Occupancy grid map built from the log: no log mapped yet. ${CURSOR_HINT}`, width: 1, height: 1, hidden: true });
    // Pointer events for drags and pinches, not the browser's own panning.
    this.canvas.style.touchAction = 'none';
    this.canvas.addEventListener('keydown', (e) => this.moveCursor(e));
    this.canvas.addEventListener('blur', () => { this.setCursor(null); this.clearCell(); });
    this.listenForViewInput();
    // The pointer left the map: its last cell would go on being read out.
    this.canvas.addEventListener('pointerleave', () => { if (!this.cursor) this.clearCell(); });
    this.viewStatus = el('p', { class: 'map-weaver-log-view occgrid-readout' });
    // The corrected map beside a dead-reckoned one: drawn whole, not
    // operated (hover, zoom, cursor, scrub and export act on the map of the
    // settings).
    this.refCanvas = el('canvas', { class: 'occgrid-map map-weaver-log-reference-map', role: 'img', 'aria-label': 'The same log mapped at its corrected poses.', width: 1, height: 1 });
    this.mainCaption = el('figcaption', { class: 'occgrid-caption' });
    this.refPane = el('figure', { class: 'map-weaver-log-reference', hidden: true },
      el('figcaption', { class: 'occgrid-caption' }, 'Corrected poses (the log’s own)'), this.refCanvas);
    this.mainPane = el('figure', { class: 'map-weaver-log-pane' }, this.mainCaption, this.canvas);
    this.stage = el('div', { class: 'map-weaver-log-stage' },
      this.mainPane, this.refPane,
      el('p', { class: 'map-weaver-log-hint' }, 'Drop a CARMEN log (.log or .log.gz) here.'));
    this.readout = el('p', { class: 'map-weaver-log-readout occgrid-readout', 'aria-live': 'polite' }, READOUT_HINT);
    this.counts = el('p', { class: 'map-weaver-log-counts occgrid-readout' });
    this.scrub = slider({ label: 'Scans integrated', min: 0, max: 1, step: 1, value: 0, format: (v) => `${count(v)} of ${count(this.total ?? 0)}`, onInput: (v) => this.seek(v), name: 'scrub' });
    this.scrub.input.disabled = true;
    this.exportButton = button('Export map', () => this.exportMap(), { name: 'export', title: 'Save the map as a ROS map_server PGM + YAML pair (one zip)' });
    this.exportButton.dataset.controls = 'export';
    this.exportButton.disabled = true;

    this.root = el('div', { class: 'map-weaver-log', dataset: { state: 'idle' } },
      el('div', { class: 'map-weaver-log-source occgrid-controls', role: 'group', 'aria-label': 'log to map', dataset: { controls: 'log-source' } },
        el('div', { class: 'occgrid-control' }, el('label', { for: fileId }, 'Open a CARMEN log'), this.fileInput),
        this.datasetMenu.root),
      el('div', { class: 'occgrid-controls', role: 'group', 'aria-label': 'grid and inverse model settings', dataset: { controls: 'log-settings' } },
        Object.values(this.controls).map((c) => c.root)),
      this.progress, this.status, this.timing,
      this.stage, this.viewStatus,
      el('div', { class: 'occgrid-controls' }, this.scrub.root, this.exportButton),
      this.readout, this.counts,
      el('p', { class: 'occgrid-caption' },
        'FLASER and ROBOTLASER1 lines are read with their corrected poses; the map covers every pose and every ',
        'reading closer than z_max, plus a metre. Each beam is traced cell by cell (Table 9.1) with the inverse model ',
        'of Table 9.2: l_occ within α/2 of the reading, l_free in front of it; a reading at or beyond z_max is a ',
        'no-return that only clears space, out to the no-return reach. Near walls, free evidence stops where a beam ',
        'grazing a wall enters its band of cells (res / sin of the incidence), so long logs keep their walls; choose ',
        'Table 9.2 to see them wear away. Scrub back and the map is rebuilt from the first scan. ',
        'Poses: the log’s are corrected (the pose oracle); its odometry fields repeat them, so dead reckoning makes its own: ',
        'each motion between two scans, split into rotate, translate, rotate, gets the odometry noise of Table 5.6 (and the drift ',
        'of slightly unequal wheels) drawn from the seed, and the noisy motions are added up from the first pose. The ',
        'dead-reckoned map is drawn beside the corrected one: its walls double and its corridors bend.'));

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

  /**
   * Shows the dataset menu when the server has /datasets/ beside /widgets/:
   * the logs its README names, or the two known ones.
   */
  async probeDatasets() {
    let names = [];
    try {
      const r = await fetch(new URL('README.md', DATASET_BASE));
      if (r.ok) {
        const text = await r.text();
        names = [...new Set(text.match(/[\w.-]+\.log(?:\.gz)?\b/g) ?? [])];
        if (names.length === 0) names = DATASETS.map(([n]) => n);
      }
    } catch {
      // Not served here: the menu stays hidden.
    }
    const known = new Map(DATASETS);
    const input = this.datasetMenu.input;
    input.replaceChildren(el('option', { value: '' }, 'choose a log…'), ...names.map((n) => el('option', { value: n }, known.get(n) ?? n)));
    this.datasetMenu.root.hidden = names.length === 0;
    this.showDataset();
  }

  /** The menu shows the /datasets/ log in the panel (or none). */
  showDataset() {
    const input = this.datasetMenu.input;
    const listed = [...input.options].some((o) => o.value === this.dataset);
    input.value = listed ? this.dataset : '';
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

  /** Reads a log and maps it, timing the whole from the reader's choice. */
  async load(name, getBytes) {
    const t0 = performance.now();
    const run = ++this.run;
    this.setState('reading');
    clearError(this.root);
    this.timing.textContent = '';
    this.progress.value = 0;
    // The previous map stays on screen, but cannot be scrubbed meanwhile.
    this.scrub.input.disabled = true;
    let session = null;
    this.trace = [];
    try {
      const bytes = await getBytes();
      if (run !== this.run) return;
      this.trace.push(['file', performance.now() - t0]);
      let t = performance.now();
      session = new this.core.LogMapSession(bytes);
      this.trace.push(['copy', performance.now() - t]);
      const requested = this.applied;
      session.configure(requested);
      let n = 128;
      let p;
      do {
        t = performance.now();
        p = session.read(n);
        const ms = performance.now() - t;
        this.trace.push(['read', ms, n]);
        n = nextChunk(n, ms);
        if (p.finished || this.progressDue()) {
          this.progress.value = READ_SHARE * (p.bytesRead / Math.max(1, p.bytesTotal));
          this.status.textContent = `Reading ${name}: ${count(p.lines)} lines, ${count(p.scans)} scans…`;
        }
        if (!p.finished) await this.pause();
        if (run !== this.run) return void session.free();
      } while (!p.finished);
      // Settings moved while the file was read: apply them before mapping.
      if (this.applied !== requested) session.configure(this.applied);
      const readMs = performance.now() - t0;
      // A log cut short is mapped up to the cut; say where it was cut.
      const warning = p.warning ? ` Warning: ${p.warning}.` : '';
      this.adopt(session, name);
      session = null;
      const built = await this.buildToTarget(run, READ_SHARE);
      if (!built) return;
      const totalMs = performance.now() - t0;
      this.root.dataset.totalMs = totalMs.toFixed(1);
      this.root.dataset.readMs = readMs.toFixed(1);
      this.timing.textContent =
        `${name}: ${count(this.lines)} lines (${count(Math.round(this.bytes / 1024))} kB) read and ${count(built.scansDone)} scans mapped ` +
        `in ${totalMs.toFixed(0)} ms, file reading included (reading ${readMs.toFixed(0)} ms).${warning}`;
    } catch (e) {
      if (run !== this.run) return void session?.free();
      this.setState('error');
      if (session?.awaitingSettings) {
        // The log is read; only its map does not fit these settings. Keep
        // it: the next change of settings maps it.
        this.adopt(session, name);
        session = null;
        this.status.textContent = `${name} is read; choose a coarser resolution or a shorter z_max to map it.`;
      } else {
        session?.free();
        // The previous map, if any, stays and can be scrubbed again.
        this.scrub.input.disabled = !this.session || !this.geometry;
        this.status.textContent = `Could not read ${name}.`;
      }
      showError(this.root, e, `${name}: `);
    }
  }

  /**
   * True at most every PROGRESS_EVERY_MS: a changed progress bar or status
   * line costs the next frame a paint of the page, and a frame between
   * every two slices would cost as much time as the slices themselves.
   */
  progressDue() {
    const now = performance.now();
    if (this.shownAt !== undefined && now - this.shownAt < PROGRESS_EVERY_MS) return false;
    this.shownAt = now;
    return true;
  }

  /**
   * Ends the task: the next call into the core runs in a new one (the trace
   * marks the boundary, so a test can see that no task holds two calls).
   */
  pause() {
    this.trace.push(['yield']);
    return yieldToEventLoop();
  }

  /**
   * The seed of dead reckoning's noise: a whole number typed in (a text that
   * is not one is refused by name, and the field shows the seed in use).
   */
  seedControl(seed) {
    const id = nextId('real-log-seed');
    const input = el('input', { type: 'number', id, name: 'seed', min: 0, max: Number.MAX_SAFE_INTEGER, step: 1, value: String(seed), inputmode: 'numeric' });
    input.addEventListener('change', () => {
      const text = input.value.trim();
      const v = Number(text);
      if (!SEED_TEXT.test(text) || !Number.isSafeInteger(v)) {
        showError(this.root, new Error(`seed ${JSON.stringify(input.value)} is not a whole number from 0 to ${Number.MAX_SAFE_INTEGER}`), 'settings: ');
        input.value = String(this.settings.seed);
        return;
      }
      this.change({ seed: v });
    });
    const root = el('div', { class: 'occgrid-control' }, el('label', { for: id }, 'Seed of the odometry noise'), input);
    return { root, input };
  }

  /** True when the settings map at dead-reckoned poses (so the corrected map is shown beside). */
  comparing(settings = this.applied) {
    return settings.poses === 'dead-reckoning';
  }

  /**
   * Makes the reference session (the corrected map) follow the main one:
   * forked from it under dead reckoning, reconfigured on a change of
   * settings, freed when the poses are the corrected ones.
   */
  syncReference() {
    if (!this.session || !this.geometry || !this.comparing()) {
      this.reference?.free();
      this.reference = null;
      this.refGeometry = null;
      this.refPane.hidden = true;
      this.mainCaption.hidden = true;
      return;
    }
    const settings = { ...this.applied, poses: 'corrected' };
    try {
      if (this.reference) this.reference.configure(settings);
      else this.reference = this.session.fork(settings);
      this.reference.seek(this.session.progress().scansTarget);
    } catch (e) {
      // The dead-reckoned map is still shown; say why its companion is not.
      showError(this.root, e, 'corrected map: ');
      this.reference?.free();
      this.reference = null;
      return this.syncReference();
    }
    this.refGeometry = this.reference.geometry();
    this.refPath = this.reference.pathPixels();
    this.refPane.hidden = false;
    this.mainCaption.hidden = false;
    this.mainCaption.textContent = `Dead reckoning (seed ${this.applied.seed})`;
  }

  /** Makes a fully read session the panel's, freeing the previous one. */
  adopt(session, name) {
    const summary = session.readSummary();
    if (this.session !== session) this.session?.free();
    this.session = session;
    this.name = name;
    this.lines = summary.lines;
    this.bytes = summary.bytesTotal;
    this.total = summary.scans;
    this.layout();
  }

  /** Sizes the canvas for the session's map (if it has one) and enables the controls. */
  layout() {
    this.geometry = this.session.geometry();
    // The last image belongs to the old geometry (or the old session), and
    // so does the last cell read out.
    this.pixels = null;
    this.cursor = null;
    this.clearCell();
    if (!this.geometry) {
      this.canvas.hidden = true;
      this.scrub.input.disabled = true;
      this.exportButton.disabled = true;
      return;
    }
    this.canvas.hidden = false;
    this.path = this.session.pathPixels();
    this.scrub.input.max = String(this.total);
    this.scrub.input.disabled = false;
    this.exportButton.disabled = false;
    this.syncReference();
    this.fitCanvas();
  }

  /**
   * Display size: the whole map's shape within the panel's width and 75%
   * of the window's height (so that the fitted view fills it). The canvas
   * has the display's device pixels
   * (bounded), and the core draws only the part of the map in view into
   * them (SPEC §11): the map's own size never reaches the page.
   */
  fitCanvas() {
    if (!this.geometry || !this.session) return;
    // Beside the corrected map, each pane gets half the width, and both the
    // same CSS pixels per cell (one log, one resolution: one scale).
    const panes = [[this.canvas, this.geometry, this.session]];
    if (this.reference && this.refGeometry) panes.push([this.refCanvas, this.refGeometry, this.reference]);
    const avail = Math.max(100, (this.stage.clientWidth - 8) / panes.length - (panes.length > 1 ? 8 : 0));
    const fit = Math.min(...panes.map(([, g]) => Math.min(avail / g.width, (0.75 * window.innerHeight) / g.height)));
    for (const [canvas, { width, height }, session] of panes) {
      const cssW = Math.max(1, Math.floor(width * fit));
      const cssH = Math.max(1, Math.floor(height * fit));
      const dpr = window.devicePixelRatio || 1;
      const k = Math.min(dpr, Math.sqrt(MAX_VIEW_PIXELS / (cssW * cssH)));
      const w = Math.max(1, Math.round(cssW * k));
      const h = Math.max(1, Math.round(cssH * k));
      canvas.style.width = `${Math.floor(cssW)}px`;
      canvas.style.height = `${Math.floor(cssH)}px`;
      if (canvas.width !== w || canvas.height !== h) {
        canvas.width = w;
        canvas.height = h;
      }
      session.setViewSize(w, h);
    }
    this.stage.classList.toggle('map-weaver-log-comparing', panes.length > 1);
    this.renderView();
    this.drawReference();
  }

  /** The corrected map beside a dead-reckoned one, whole, with its path and robot. */
  drawReference() {
    if (!this.reference || !this.refGeometry) return;
    const ptr = this.reference.renderView();
    const v = this.reference.view();
    drawMapImage(this.refCanvas, this.memory, ptr, v.width, v.height);
    const ctx = this.refCanvas.getContext('2d');
    ctx.save();
    ctx.setTransform(v.scale, 0, 0, v.scale, -v.u0 * v.scale, -v.v0 * v.scale);
    const dpr = this.refCanvas.width / Math.max(1, this.refCanvas.clientWidth || this.refCanvas.width);
    const unit = dpr / v.scale;
    const done = this.reference.progress().scansDone;
    if (this.refPath && done >= 1) {
      drawPath(ctx, 1, this.refPath, done, { color: PATH_COLOR, lineWidth: unit });
      drawRobot(ctx, 1, this.reference.robotAt(done - 1), {
        color: ROBOT_COLOR, radius: 4 * unit, tick: 10 * unit, lineWidth: 1.5 * unit,
      });
    }
    ctx.restore();
  }

  /** Draws the view of the map the core holds (no map-sized image: the view's pixels only). */
  renderView() {
    if (!this.session || !this.geometry) return;
    this.pixels = this.session.renderView();
    this.view = this.session.view();
    this.redraw();
    const v = this.view;
    const dpr = this.canvas.width / Math.max(1, this.canvas.clientWidth || this.canvas.width);
    const perCell = v.scale / dpr;
    const res = this.geometry.resolution;
    const [wx, wy] = [(v.width / v.scale) * res, (v.height / v.scale) * res];
    this.viewStatus.textContent =
      `view: ${perCell >= 1 ? `${fixed(perCell, 1)} screen pixels per cell` : `${fixed(1 / perCell, 1)} cells per screen pixel`}, ` +
      `${fixed(wx, 1)} m × ${fixed(wy, 1)} m shown · wheel or pinch to zoom, drag to pan, + − 0 and arrows on the focused map`;
    Object.assign(this.root.dataset, { viewScale: String(v.scale), viewWidth: String(v.width), viewHeight: String(v.height) });
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
      this.session.zoomAt(x, y, Math.exp(-e.deltaY * px * WHEEL_ZOOM_PER_PX));
      this.renderView();
      this.readViewCell(x, y);
    }, { passive: false });
    this.canvas.addEventListener('pointerdown', (e) => {
      if (!this.view) return;
      this.canvas.setPointerCapture?.(e.pointerId);
      pointers.set(e.pointerId, this.viewPoint(e));
      last = pointers.size === 2 ? pinch() : null;
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
        if (this.cursor) this.setCursor(null);
        this.readViewCell(p.x, p.y);
        return;
      }
      pointers.set(e.pointerId, p);
      if (pointers.size === 1) {
        this.session.panBy(p.x - before.x, p.y - before.y);
      } else if (pointers.size === 2) {
        const now = pinch();
        if (last && last.d > 0) {
          this.session.panBy(now.x - last.x, now.y - last.y);
          this.session.zoomAt(now.x, now.y, now.d / last.d);
        }
        last = now;
      }
      this.renderView();
    });
  }

  /**
   * Integrates scans towards the session's target (and the corrected map's
   * beside it, one call each in turn), a time slice per call: each call
   * does a budget of cell updates sized from the last call's duration
   * (`buildSlice`), and drawing gets a task of its own (the corrected map's
   * another).
   */
  async buildToTarget(run, offset = 0) {
    this.setState('building');
    const jobs = [{ session: this.session, main: true }];
    if (this.reference) jobs.push({ session: this.reference, main: false });
    // Both maps share the budget: one log, one machine, one speed.
    let cells = this.sliceCells ?? FIRST_SLICE_CELLS;
    let drawn = performance.now();
    let turn = 0;
    let main = null;
    // Setting the map up (reading's last call, or new settings) had a task
    // of its own.
    await this.pause();
    if (run !== this.run) return null;
    for (;;) {
      const open = jobs.filter((j) => !j.done);
      const job = open[turn++ % open.length];
      const last = job.last ?? job.session.progress();
      const t = performance.now();
      let p;
      try {
        p = job.session.buildSlice(cells);
      } catch (e) {
        // The map's tiles would pass their budget (the core says how much
        // the log needs): the map so far stays on screen.
        this.renderView();
        this.drawReference();
        this.setState('error');
        this.status.textContent = 'The map stopped short: choose a coarser resolution.';
        showError(this.root, e, job.main ? 'map: ' : 'corrected map: ');
        return null;
      }
      const ms = performance.now() - t;
      const did = p.cellUpdates - last.cellUpdates;
      this.trace.push(['build', ms, cells, did, p.scansDone]);
      job.msPerScan = ms / Math.max(1, p.scansDone - last.scansDone);
      cells = nextChunk(cells, ms, did);
      this.sliceCells = cells;
      job.last = p;
      job.done = p.finished;
      if (job.main) main = p;
      const finished = jobs.every((j) => j.done);
      const due = finished || this.progressDue();
      if (due) {
        const progress = jobs.reduce((a, j) => a + (j.last ? j.last.scansDone / Math.max(1, j.last.scansTarget) : 0), 0) / jobs.length;
        this.progress.value = offset + (1 - offset) * (main?.scansTarget === 0 ? 1 : progress);
        if (main) this.scrub.set(main.scansDone);
      }
      // No intermediate frame when the build is about to finish anyway.
      const remaining = open.reduce((a, j) => a + (j.last ? (j.last.scansTarget - j.last.scansDone) * j.msPerScan : 0), 0);
      if (finished || (performance.now() - drawn > DRAW_EVERY_MS && remaining > DRAW_EVERY_MS)) {
        const steps = [() => this.draw(main ?? this.session.progress())];
        if (this.reference) steps.push(() => this.drawReference());
        for (const step of steps) {
          await this.pause();
          if (run !== this.run) return null;
          const t1 = performance.now();
          step();
          drawn = performance.now();
          this.trace.push(['draw', drawn - t1]);
        }
      } else if (due) {
        this.status.textContent = `Mapping: scan ${count(main?.scansDone ?? 0)} of ${count(main?.scansTarget ?? this.total)}…`;
      }
      if (finished) {
        this.setState('done');
        return main;
      }
      await this.pause();
      if (run !== this.run) return null;
    }
  }

  draw(p) {
    this.done = p.scansDone;
    this.renderView();
    const { width, height } = this.geometry;
    const c = this.session.counts();
    this.status.textContent = p.finished
      ? `${count(p.scansDone)} of ${count(p.scansTotal)} scans, ${count(p.beams)} beams, ${count(p.cellUpdates)} cell updates · ` +
        `map ${count(width)} × ${count(height)} cells at ${this.geometry.resolution} m`
      : `Mapping: scan ${count(p.scansDone)} of ${count(p.scansTarget)}…`;
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
      `Occupancy grid map of ${this.name}, ${count(width)} × ${count(height)} cells of ${this.geometry.resolution} m, ` +
      `after ${count(p.scansDone)} of ${count(p.scansTotal)} scans: ${count(c.occupied)} cells occupied (${occ}), ${count(c.free)} free (${free}), ` +
      `${count(c.unknown)} unknown. Gray is unknown, white free, black occupied; the green line is the laser’s path. ${CURSOR_HINT}`);
  }

  /**
   * Draws the last rendered view (no core call), the laser's path up to the
   * last integrated scan with the robot where it is now, and the keyboard
   * cursor, through the view's transform (image units to canvas pixels),
   * their widths in screen pixels at any zoom.
   */
  redraw() {
    if (!this.pixels || !this.view) return;
    const v = this.view;
    drawMapImage(this.canvas, this.memory, this.pixels, v.width, v.height);
    const ctx = this.canvas.getContext('2d');
    ctx.save();
    ctx.setTransform(v.scale, 0, 0, v.scale, -v.u0 * v.scale, -v.v0 * v.scale);
    const dpr = this.canvas.width / Math.max(1, this.canvas.clientWidth || this.canvas.width);
    const unit = dpr / v.scale;
    if (this.path && this.done >= 1) {
      drawPath(ctx, 1, this.path, this.done, { color: PATH_COLOR, lineWidth: unit });
      drawRobot(ctx, 1, this.session.robotAt(this.done - 1), {
        color: ROBOT_COLOR, radius: 4 * unit, tick: 10 * unit, lineWidth: 1.5 * unit,
      });
    }
    if (this.cursor) {
      outlineCell(ctx, 1, this.cursor, { color: CURSOR_COLOR, lineWidth: 2 * unit, pad: 2 * unit });
    }
    ctx.restore();
  }

  /**
   * Arrow keys move a cursor over the map, a few screen pixels (at least a
   * cell) per press, ten times as far with Shift, and the view follows it;
   * + and - zoom about it, 0 shows the whole map.
   */
  moveCursor(e) {
    if (!this.geometry || !this.view) return;
    const { width, height } = this.geometry;
    const v = this.view;
    const here = this.cursor ?? this.centreCell();
    if (e.key === '+' || e.key === '=' || e.key === '-' || e.key === '_' || e.key === '0') {
      e.preventDefault();
      if (e.key === '0') this.session.fitView();
      else {
        const x = (here.col + 0.5 - v.u0) * v.scale;
        const y = (here.row + 0.5 - v.v0) * v.scale;
        this.session.zoomAt(x, y, e.key === '+' || e.key === '=' ? KEY_ZOOM : 1 / KEY_ZOOM);
      }
      this.cursor = here;
      this.renderView();
      this.readCell(here.col, here.row);
      return;
    }
    const step = Math.max(1, Math.round(CURSOR_STEP_PX / v.scale)) * (e.shiftKey ? 10 : 1);
    const to = arrowCell(e, here, width, height, step);
    if (!to) return;
    e.preventDefault();
    this.cursor = to;
    // Off screen (or at its edge): bring it back to the centre.
    const x = (to.col + 0.5 - v.u0) * v.scale;
    const y = (to.row + 0.5 - v.v0) * v.scale;
    const m = Math.min(v.width, v.height) * 0.05;
    if (x < m || y < m || x > v.width - m || y > v.height - m) {
      this.session.panBy(v.width / 2 - x, v.height / 2 - y);
    }
    this.renderView();
    this.readCell(to.col, to.row);
  }

  /** The map image cell at the view's centre. */
  centreCell() {
    const v = this.view;
    const { width, height } = this.geometry;
    const clamp = (a, n) => Math.max(0, Math.min(n - 1, Math.floor(a)));
    return { col: clamp(v.u0 + v.width / (2 * v.scale), width), row: clamp(v.v0 + v.height / (2 * v.scale), height) };
  }

  /** Reads out the cell under canvas pixel `(x, y)` of the view. */
  readViewCell(x, y) {
    const c = this.session?.cellAtView(x, y);
    if (c) this.showReadout(c);
  }

  setCursor(cursor) {
    this.cursor = cursor;
    this.redraw();
  }

  readCell(col, row) {
    if (col < 0 || row < 0) return;
    const c = this.session.cellAt(col, row);
    if (c) this.showReadout(c);
  }

  showReadout(c) {
    this.readout.dataset.x = String(c.x);
    this.readout.dataset.y = String(c.y);
    this.readout.dataset.ix = String(c.ix);
    this.readout.dataset.iy = String(c.iy);
    this.readout.dataset.l = String(c.l);
    this.readout.dataset.p = String(c.p);
    this.readout.dataset.updates = String(c.updates);
    this.readout.textContent =
      `cell (${c.ix}, ${c.iy}) at (${fixed(c.x, 2)} m, ${fixed(c.y, 2)} m): l = ${fixed(c.l, 3)}, p = ${fixed(c.p, 3)}, ` +
      `${count(c.updates)} update${c.updates === 1 ? '' : 's'}`;
  }

  /** The cell readout with no cell pointed at (its values would be stale). */
  clearCell() {
    this.readout.textContent = READOUT_HINT;
    for (const k of ['x', 'y', 'ix', 'iy', 'l', 'p', 'updates']) delete this.readout.dataset[k];
  }

  /** After a rebuild or a scrub: the keyboard cursor's cell read again, else no cell. */
  rereadCell() {
    if (this.cursor) this.readCell(this.cursor.col, this.cursor.row);
    else this.clearCell();
  }

  /** A control moved: rebuild with the new settings (the core validates them). */
  change(patch) {
    this.settings = { ...this.settings, ...patch };
    clearTimeout(this.changeTimer);
    // Wait for the slider to settle: each rebuild restarts from scan 0.
    this.changeTimer = setTimeout(() => this.reconfigure(), 120);
  }

  async reconfigure() {
    if (!this.session || this.root.dataset.state === 'reading') {
      // Nothing mapped yet, or a log is being read: `load` applies them.
      this.applied = { ...this.settings };
      return;
    }
    const run = ++this.run;
    try {
      this.session.configure(this.settings);
      this.applied = { ...this.settings };
      clearError(this.root);
    } catch (e) {
      showError(this.root, e, 'settings: ');
      this.settings = { ...this.applied };
      this.syncControls();
      return;
    }
    this.layout();
    // The load's timing line was for the settings it was mapped with.
    const t0 = performance.now();
    this.timing.textContent = '';
    this.clearCell();
    const built = await this.buildToTarget(run);
    if (!built || run !== this.run) return;
    this.timing.textContent =
      `Rebuilt with the new settings (${this.applied.resolution} m cells): ${count(built.scansDone)} scans mapped in ${(performance.now() - t0).toFixed(0)} ms.`;
    this.rereadCell();
  }

  syncControls() {
    const s = this.settings;
    this.controls.resolution.input.value = String(s.resolution);
    this.controls.walls.input.value = String(s.walls);
    this.controls.poses.input.value = String(s.poses);
    this.controls.seed.input.value = String(s.seed);
    for (const key of ['rangeCap', 'alpha', 'lOcc', 'lFree', 'clamp', 'noReturnReach']) this.controls[key].set(s[key]);
  }

  async seek(k) {
    if (!this.session) return;
    const run = ++this.run;
    try {
      this.session.seek(k);
      this.reference?.seek(k);
    } catch (e) {
      return void showError(this.root, e, 'scrub: ');
    }
    this.clearCell();
    await this.buildToTarget(run);
    if (run === this.run) this.rereadCell();
  }

  exportMap() {
    if (!this.session) return;
    const stem = mapStem(this.name);
    return exportMap(this.root, stem, () => this.session.exportMap(stem), 'export: ');
  }

  setState(state) {
    this.root.dataset.state = state;
    this.root.setAttribute('aria-busy', String(state === 'reading' || state === 'building'));
  }
}


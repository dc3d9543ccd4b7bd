// <occgrid-sensor-fusion>: two sensors, two questions, and the max rule
// (Probabilistic Robotics eq. 9.9; SPEC §8, §10.4).
//
// A robot drives a lap around a table. A sonar ring at table height sees
// the top; a LiDAR at shin height threads its beams between the four legs.
// Four maps side by side: each sensor's own grid, the two fused by
// p = max(p_sonar, p_lidar), and one grid fed both streams. The reader moves
// the LiDAR's beam count and watches the summed table appear or vanish while
// the max-fused table stays. Every number shown comes from the wasm core;
// this module only draws and forwards input.
//
// Attributes: lidar-beams (a whole number, 1 to 2048), seed (a whole number).
import { loadCore } from './lib/core.js';
import { COLORS } from './lib/chart.js';
import { downloadMapPair } from './lib/export.js';
import {
  el, slider, button, showError, clearError, ensureStyles, hiDpiCanvas, drawMap,
  whenVisible, prefersReducedMotion, fixed,
} from './lib/ui.js';

/** Beam counts the slider offers (an attribute may add another). */
const BEAM_STEPS = [4, 6, 8, 12, 16, 24, 36, 45, 60, 90, 120, 180, 360, 720];
const DEFAULT_BEAMS = 360;
/** Scans per second while playing. */
const STEPS_PER_SECOND = 12;
/** Largest drawn map, CSS pixels. */
const MAX_CSS_WIDTH = 440;
const FOOTPRINT_COLOR = COLORS.series[3];
const ROBOT_COLOR = COLORS.series[1];

const PANES = [
  { key: 'sonar', title: 'Sonar grid', describe: (r) => `${r.sonarCount} cones of ${fixed(r.sonarConeDegrees, 0)}°, at table height` },
  { key: 'lidar', title: 'LiDAR grid', describe: (r) => `${r.lidarBeams} beams, at shin height` },
  { key: 'max', title: 'Max fusion', describe: () => 'p = max(p_sonar, p_lidar), eq. 9.9' },
  { key: 'sum', title: 'Summation', describe: () => 'one grid, both streams added' },
];

function parseWhole(name, text, min, max) {
  const v = Number(text);
  if (text.trim() === '' || !Number.isInteger(v) || v < min || v > max) {
    throw new Error(`invalid ${name}: "${text}" (expected a whole number from ${min} to ${max})`);
  }
  return v;
}

class SensorFusionElement extends HTMLElement {
  static observedAttributes = ['lidar-beams', 'seed'];

  constructor() {
    super();
    this.beams = DEFAULT_BEAMS;
    this.seed = null;
    this.sim = null;
    this.playing = false;
    this.frame = 0;
  }

  async connectedCallback() {
    if (this.built) return;
    this.built = true;
    ensureStyles();
    this.build();
    try {
      ({ core: this.core, memory: this.memory } = await loadCore());
    } catch (e) {
      showError(this, e, 'could not load the core: ');
      return;
    }
    this.readAttributes();
    this.create();
    whenVisible(this, () => {
      if (!prefersReducedMotion() && this.sim) this.play();
    });
  }

  disconnectedCallback() {
    this.pause();
  }

  attributeChangedCallback(name) {
    if (!this.core) return;
    const seedBefore = this.seed;
    if (!this.readAttributes()) return;
    if (name === 'seed' && this.seed !== seedBefore) this.create();
    else if (name === 'lidar-beams') this.requestBeams(this.beams);
  }

  /**
   * Reads the attributes; a bad value is shown in the widget (false), and
   * the widget keeps working with the last good values.
   */
  readAttributes() {
    try {
      const beams = this.getAttribute('lidar-beams');
      const seed = this.getAttribute('seed');
      if (beams !== null) this.beams = parseWhole('lidar-beams', beams, 1, 2048);
      if (seed !== null) this.seed = parseWhole('seed', seed, 0, Number.MAX_SAFE_INTEGER);
      clearError(this);
      return true;
    } catch (e) {
      showError(this, e);
      return false;
    }
  }

  build() {
    this.steps = [...BEAM_STEPS];
    this.playButton = button('Play', () => (this.playing ? this.pause() : this.play()), { name: 'play', pressed: false });
    this.beamSlider = slider({
      label: 'LiDAR beams',
      min: 0, max: this.steps.length - 1, step: 1,
      value: this.steps.indexOf(DEFAULT_BEAMS),
      format: (i) => String(this.steps[i] ?? ''),
      onInput: (i) => this.requestBeams(this.steps[i]),
      name: 'lidar-beams',
    });
    this.status = el('p', { class: 'occgrid-readout sensor-fusion-status', 'aria-live': 'polite' }, 'Loading…');
    this.panes = PANES.map((p) => {
      const canvas = el('canvas', { class: 'occgrid-map sensor-fusion-map', role: 'img', 'aria-label': `${p.title} map` });
      const note = el('span', { class: 'sensor-fusion-note' });
      const mean = el('output', { class: 'sensor-fusion-mean', 'aria-live': 'off' }, '–');
      const exportButton = button('Export map', () => this.exportMap(p.key), { name: `export-${p.key}`, title: `Save the ${p.title.toLowerCase()} as a ROS map_server PGM + YAML pair` });
      exportButton.setAttribute('aria-label', `Export the ${p.title.toLowerCase()}`);
      const root = el('figure', { class: `sensor-fusion-pane sensor-fusion-${p.key}`, dataset: { map: p.key } },
        el('figcaption', {}, el('strong', {}, p.title), ' ', note),
        canvas,
        el('div', { class: 'sensor-fusion-foot' },
          el('span', {}, 'footprint mean occupancy ', mean),
          exportButton));
      return { ...p, canvas, note, mean, root };
    });
    this.append(
      el('div', { class: 'occgrid-controls' },
        this.playButton,
        button('Step', () => { this.pause(); this.advance(1); }, { name: 'step' }),
        button('Reset', () => { this.pause(); this.sim && this.sim.reset(); this.draw(); }, { name: 'reset' }),
        this.beamSlider.root),
      this.status,
      el('div', { class: 'sensor-fusion-panes' }, this.panes.map((p) => p.root)),
      el('p', { class: 'occgrid-caption' },
        'The dashed outline is the table top. The sonar sees its rim and cannot see past it; the LiDAR sees four legs and free floor between them. ',
        'Both are right about their own slice. Max fusion keeps one map per sensor and takes the more occupied answer per cell, so the table stays an obstacle ',
        '(and a cell stays gray wherever one sensor has not looked yet: unknown, p = 0.5, outranks free). ',
        'Summation adds both streams into one grid as if they measured the same thing: the table’s probability then follows whichever sensor delivers more evidence. ',
        'Lower the beam count and the summed table comes back; the table never changed.'),
    );
    if ('ResizeObserver' in window) {
      this.resizer = new ResizeObserver(() => this.layout());
      this.resizer.observe(this.querySelector('.sensor-fusion-panes'));
    }
  }

  /** (Re)creates the experiment in the core from the attributes. */
  create() {
    this.pause();
    try {
      const scene = this.seed === null ? undefined : { seed: this.seed };
      const next = new this.core.SensorFusion(scene, undefined);
      if (this.beams !== DEFAULT_BEAMS) next.setLidarBeams(this.beams);
      this.sim?.free();
      this.sim = next;
      clearError(this);
    } catch (e) {
      showError(this, e);
      return;
    }
    this.syncSlider();
    this.layout();
  }

  syncSlider() {
    if (!this.steps.includes(this.beams)) {
      this.steps = [...BEAM_STEPS, this.beams].sort((a, b) => a - b);
      this.beamSlider.input.max = String(this.steps.length - 1);
    }
    this.beamSlider.set(this.steps.indexOf(this.beams));
  }

  /** Applies the latest requested beam count, one rebuild at a time. */
  requestBeams(n) {
    this.wantBeams = n;
    if (this.beamTask || !this.sim) return;
    this.beamTask = setTimeout(() => {
      this.beamTask = null;
      const beams = this.wantBeams;
      try {
        this.sim.setLidarBeams(beams);
        this.beams = beams;
        clearError(this);
      } catch (e) {
        showError(this, e);
      }
      this.syncSlider();
      this.draw();
      this.announce();
    }, 0);
  }

  /** Sizes the canvases to their panes (hi-DPI) and redraws. */
  layout() {
    if (!this.sim) return;
    const { width: w, height: h } = this.sim;
    for (const p of this.panes) {
      const cssW = Math.max(120, Math.min(MAX_CSS_WIDTH, Math.floor(p.root.clientWidth || 300)));
      if (p.cssW === cssW) continue;
      p.cssW = cssW;
      p.ctx = hiDpiCanvas(p.canvas, cssW, Math.round((cssW * h) / w));
    }
    this.draw();
  }

  play() {
    if (!this.sim || this.playing) return;
    const r = this.sim.readout();
    if (r.step >= r.steps) this.sim.reset();
    this.playing = true;
    this.playButton.textContent = 'Pause';
    this.playButton.setAttribute('aria-pressed', 'true');
    let last = performance.now();
    let owed = 0;
    const tick = (now) => {
      if (!this.playing) return;
      owed += ((now - last) / 1000) * STEPS_PER_SECOND;
      last = now;
      const n = Math.min(4, Math.floor(owed));
      if (n > 0) {
        owed -= n;
        if (!this.advance(n)) {
          this.pause();
          return;
        }
      }
      this.frame = requestAnimationFrame(tick);
    };
    this.frame = requestAnimationFrame(tick);
  }

  pause() {
    if (this.frame) cancelAnimationFrame(this.frame);
    this.frame = 0;
    if (!this.playing) return;
    this.playing = false;
    this.playButton.textContent = 'Play';
    this.playButton.setAttribute('aria-pressed', 'false');
    this.announce();
  }

  /** Integrates up to `n` steps; false once the lap is over. */
  advance(n) {
    if (!this.sim) return false;
    let moved = true;
    for (let i = 0; i < n && moved; i++) moved = this.sim.step();
    this.draw();
    if (!this.playing) this.announce();
    return moved;
  }

  /** Draws the four maps and the readouts from the core's current state. */
  draw() {
    if (!this.sim) return;
    let r, view;
    try {
      r = this.sim.readout();
      view = this.sim.sceneView();
      const { width: w, height: h } = this.sim;
      for (const p of this.panes) {
        if (!p.ctx) continue;
        drawMap(p.canvas, this.memory, this.sim.render(p.key), w, h);
        this.overlay(p, view, w, h);
        p.note.textContent = `· ${p.describe(r)}`;
        const mean = r.footprint[p.key];
        p.mean.textContent = fixed(mean, 3);
        p.mean.dataset.value = String(mean);
      }
    } catch (e) {
      showError(this, e);
      this.pause();
      return;
    }
    this.dataset.step = String(r.step);
    this.dataset.lidarBeams = String(r.lidarBeams);
    this.dataset.maxMean = String(r.footprint.max);
    this.dataset.sumMean = String(r.footprint.sum);
    this.reading = r;
    if (this.playing) this.status.setAttribute('aria-live', 'off');
    this.statusText(r);
  }

  statusText(r) {
    this.status.textContent =
      `Scan ${r.step} of ${r.steps}. Mean occupancy over the table’s ${r.footprintCells} cells: ` +
      `max fusion ${fixed(r.footprint.max, 3)}, summation ${fixed(r.footprint.sum, 3)} ` +
      `(sonar alone ${fixed(r.footprint.sonar, 3)}, LiDAR alone ${fixed(r.footprint.lidar, 3)}).`;
  }

  /** Lets screen readers hear the state once the motion stops. */
  announce() {
    this.status.setAttribute('aria-live', 'polite');
    if (this.reading) this.statusText(this.reading);
  }

  /** Footprint, robot and the current scan, in the map's own cells. */
  overlay(p, view, w, h) {
    const ctx = p.ctx;
    const s = p.cssW / w;
    const X = (u) => u * s;
    const Y = (v) => (h - v) * s;
    const [u, v, theta] = view.robot;
    ctx.save();
    if (p.key === 'sonar' && view.sonar.length) {
      ctx.fillStyle = COLORS.evidence + '30';
      ctx.strokeStyle = COLORS.evidence;
      ctx.lineWidth = 1;
      for (const c of view.sonar) {
        const r = c.range * s;
        ctx.beginPath();
        ctx.moveTo(X(u), Y(v));
        ctx.arc(X(u), Y(v), r, -c.angle - view.sonarHalfWidth, -c.angle + view.sonarHalfWidth);
        ctx.closePath();
        ctx.fill();
        ctx.beginPath();
        ctx.arc(X(u), Y(v), r, -c.angle - view.sonarHalfWidth, -c.angle + view.sonarHalfWidth);
        ctx.stroke();
      }
    }
    if (p.key === 'lidar' && view.lidar.length) {
      ctx.strokeStyle = COLORS.evidence + '80';
      ctx.lineWidth = 0.75;
      ctx.beginPath();
      for (let i = 0; i + 1 < view.lidar.length; i += 2) {
        ctx.moveTo(X(u), Y(v));
        ctx.lineTo(X(view.lidar[i]), Y(view.lidar[i + 1]));
      }
      ctx.stroke();
    }
    const [u0, v0, u1, v1] = view.footprint;
    ctx.setLineDash([5, 3]);
    ctx.strokeStyle = FOOTPRINT_COLOR;
    ctx.lineWidth = 1.5;
    ctx.strokeRect(X(u0), Y(v1), X(u1) - X(u0), Y(v0) - Y(v1));
    ctx.setLineDash([]);
    ctx.fillStyle = ROBOT_COLOR;
    ctx.strokeStyle = ROBOT_COLOR;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(X(u), Y(v), 4, 0, 2 * Math.PI);
    ctx.fill();
    ctx.beginPath();
    ctx.moveTo(X(u), Y(v));
    ctx.lineTo(X(u) + 10 * Math.cos(theta), Y(v) - 10 * Math.sin(theta));
    ctx.stroke();
    ctx.restore();
  }

  /** Saves one map as a ROS map_server pair (PGM + YAML, in one zip). */
  async exportMap(key) {
    if (!this.sim) return;
    try {
      await downloadMapPair(`table-${key}`, this.sim.exportMap(key));
    } catch (e) {
      showError(this, e);
    }
  }
}

if (!customElements.get('occgrid-sensor-fusion')) customElements.define('occgrid-sensor-fusion', SensorFusionElement);

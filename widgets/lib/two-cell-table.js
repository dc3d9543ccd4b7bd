// The two-cell table of <occgrid-doorway-trap> (Probabilistic Robotics §9.4,
// docs/ARCHITECTURE.md, "Sessions and panes"): the exact joint posterior of two cells inside one sonar cone
// against the product of their marginals, with the cells movable (drag, or
// the arrow keys, as the diagram says under it) and the reading and the
// prior adjustable; below the table, the joint entropy against the sum of
// the marginal entropies a factored map states, and the gap between them.
// The core (`jointPosterior`, `chapterTwoCellQuery`) computes every number;
// this module lays out the diagram and the table, draws and forwards input.
//
// Usage: `const t = new TwoCellTable(host, { reading, prior })`, append
// `t.root` to the widget, then `t.start(core, values)` once the core is
// loaded and again whenever the attributes `arrangement`, `cells`,
// `reading` or `prior` change; `t.linkState()` gives them back as they are
// now. The table's own errors are shown in its own box, inside `t.root`,
// so that clearing them never clears a refusal the widget shows above it.
import { COLORS } from './chart.js';
import { el, slider, button, hiDpiCanvas, fixed } from './ui.js';
import { invalidValue } from './attributes.js';
import { drawCones } from './layers.js';

/** The core's presets of the two cells (`twoCellPreset`). */
const PRESETS = ['side', 'collinear', 'apart'];
/** The diagram's reach, metres. */
const DIAGRAM_RANGE = 3.1;
/** The two-cell diagram, CSS pixels: the cone lies on its side, sensor at the left. */
const DIAGRAM_W = 440;
const DIAGRAM_H = 200;
const POSE_COLOR = COLORS.series[1];

/**
 * The `cells` attribute: "rangeA,bearingA,rangeB,bearingB" (metres,
 * degrees), ranges from the nearest the table places a cell
 * (`constants().limits.twoCellTable.reading.min`) up to the sonar's z_max
 * and bearings within the cone's half-width: the core's
 * `constants().twoCellTable` ({ maxRange, halfConeDeg }).
 */
export function cellsType({ minRange, maxRange, halfConeDeg }) {
  return {
    describe: `four numbers "rangeA, bearingA, rangeB, bearingB": ranges from ${minRange} to ${maxRange} m, bearings from -${halfConeDeg} to ${halfConeDeg}°`,
    parse(text, name) {
      const v = text.split(/[\s,;]+/).filter(Boolean).map(Number);
      const ok = v.length === 4 && v.every(Number.isFinite) &&
        [v[0], v[2]].every((r) => r >= minRange && r <= maxRange) &&
        [v[1], v[3]].every((b) => Math.abs(b) <= halfConeDeg);
      if (!ok) throw invalidValue(name, text, this.describe);
      return [{ range: v[0], bearing_deg: v[1] }, { range: v[2], bearing_deg: v[3] }];
    },
  };
}

const bits = (occupied) => occupied.map((o) => (o ? '1' : '0')).join(' ');

export class TwoCellTable {
  /** `reading` and `prior`: the sliders' starting values. */
  constructor(host, { reading, prior }) {
    this.host = host;
    this.core = null;
    this.query = null;
    this.minRange = 0;
    this.jointReport = null;
    this.arrangement = null;
    this.movingCell = 1; // which point the arrow keys move (0 = A, 1 = B)
    this.root = this.build(reading, prior);
  }

  /** The table's attributes as they are now, for "Copy link". */
  linkState() {
    const q = this.query;
    const custom = this.arrangement === 'custom' && q;
    return {
      arrangement: custom ? null : this.arrangement,
      cells: custom ? q.cells.map((c) => `${fixed(c.range, 2)},${fixed(c.bearing_deg, 1)}`).join(',') : null,
      reading: q ? q.readings[0].toFixed(2) : null,
      prior: q ? q.prior.toFixed(2) : null,
    };
  }

  build(reading, prior) {
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
      // The core's range (up to the query's z_max), set once it has loaded.
      label: 'Reading z', min: 0, step: 'any', value: reading,
      format: (v) => (this.query && v >= this.query.model.z_max ? `${v.toFixed(2)} m (no echo)` : `${v.toFixed(2)} m`),
      onInput: (v) => { if (this.query) { this.query.readings = [v]; this.updateJoint(); } },
      name: 'reading',
    });
    this.priorSlider = slider({
      label: 'Prior p₀', min: 0, max: 1, step: 'any', value: prior,
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
    this.entropyOut = el('p', { class: 'occgrid-readout doorway-trap-entropy' });
    this.trapOut = el('p', { class: 'occgrid-readout doorway-trap-verdict', 'aria-live': 'polite' });
    // Styled as an error (.occgrid-error) only while it holds one.
    this.errorBox = el('p', { class: 'doorway-trap-two-cell-error', role: 'alert', hidden: true });

    this.diagram.addEventListener('pointerdown', (ev) => this.dragStart(ev));
    this.diagram.addEventListener('pointermove', (ev) => this.dragMove(ev));
    this.diagram.addEventListener('pointerup', (ev) => this.dragEnd(ev));
    this.diagram.addEventListener('pointercancel', (ev) => this.dragEnd(ev));
    this.diagram.addEventListener('keydown', (ev) => this.nudge(ev));
    this.diagram.addEventListener('focus', () => this.query && this.drawDiagram());
    this.diagram.addEventListener('blur', () => this.query && this.drawDiagram());

    return el('section', { class: 'doorway-trap-two-cell', 'aria-label': 'Two cells, one cone' },
      el('h3', {}, 'Two cells, one cone'),
      this.errorBox,
      el('div', { class: 'doorway-trap-two-cell-layout' },
        el('div', { class: 'doorway-trap-diagram-box' },
          this.diagram,
          el('p', { class: 'occgrid-caption doorway-trap-drag-hint' },
            'Drag A or B to move it (mouse or touch), or click the diagram and use the arrow keys: ',
            '← → in range, ↑ ↓ in bearing; Space switches between A and B.'),
          el('div', { class: 'occgrid-buttons', role: 'group', 'aria-label': 'arrangement of the two cells', dataset: { controls: 'arrangements' } }, this.arrangementButtons),
          this.readingSlider.root, this.priorSlider.root),
        el('div', { class: 'doorway-trap-table-box' },
          // Scrolls sideways in a narrow column; focusable so the keyboard can scroll it.
          el('div', { class: 'occgrid-scroll', tabindex: 0, role: 'region', 'aria-label': 'Joint posterior table' }, this.jointTable),
          this.marginalsOut, this.entropyOut, this.trapOut,
          el('p', { class: 'occgrid-caption' },
            'Both cells start at the prior. One echo from inside the cone says that something in it is occupied, not which cell: ',
            'the exact posterior puts almost no mass on “both free”, while the factored map, which keeps only p_A and p_B, ',
            'multiplies them and finds “both free” many times too likely. Put B behind A and it hides; move it in front of the echo and it is simply free. ',
            '“Collinear” is the chapter’s exercise: A at 1 m and B at 2 m on the axis, reading 2.0 m. A free A and an occupied B explain the echo; ',
            'an occupied A would have answered at 1 m, so “both occupied” is unlikely, yet the product of marginals finds it about twice too likely.'))));
  }

  /** Sets up the table from the attributes `arrangement`, `cells`, `reading` and `prior`. */
  start(core, v) {
    this.core = core;
    try {
      this.query = this.core.chapterTwoCellQuery();
    } catch (e) {
      this.showError(e);
      return;
    }
    this.query.readings = [v.reading];
    this.query.prior = v.prior;
    // The sliders' ranges and the nearest a cell may be placed: the core's
    // (`constants().limits.twoCellTable`; the reading's up to the sonar's z_max).
    const limits = this.core.constants().limits.twoCellTable;
    this.minRange = limits.reading.min;
    this.readingSlider.setRange(limits.reading);
    this.priorSlider.setRange(limits.prior);
    this.readingSlider.set(v.reading);
    this.priorSlider.set(v.prior);
    if (!v.cells) {
      this.setArrangement(v.arrangement);
      return;
    }
    // Cells placed where a preset puts them count as that preset.
    let presets;
    try {
      presets = Object.fromEntries(PRESETS.map((k) => [k, this.core.twoCellPreset(k).cells]));
    } catch (e) {
      this.showError(e);
      return;
    }
    const same = (a, b) => a.every((c, j) => Math.abs(c.range - b[j].range) < 1e-9 && Math.abs(c.bearing_deg - b[j].bearing_deg) < 1e-9);
    const preset = Object.keys(presets).find((k) => same(v.cells, presets[k]));
    if (preset) this.setArrangement(preset);
    else {
      this.query.cells = v.cells.map((c) => ({ ...c }));
      this.moveCell(1, this.query.cells[1].range, this.query.cells[1].bearing_deg);
    }
  }

  setArrangement(key) {
    if (!this.core) return;
    let cells;
    try {
      cells = this.core.twoCellPreset(key).cells;
      if (!this.query) this.query = this.core.chapterTwoCellQuery();
    } catch (e) {
      this.showError(e);
      return;
    }
    this.query.cells = cells.map((c) => ({ ...c }));
    this.arrangement = key;
    for (const b of this.arrangementButtons) b.setAttribute('aria-pressed', String(b.dataset.arrangement === key));
    this.updateJoint();
  }

  /** Shows a refusal of the table's in its own box (and in the console). */
  showError(error) {
    const message = error && error.message ? error.message : String(error);
    console.error(`${this.host.localName}: two-cell table: ${message}`);
    this.errorBox.textContent = message;
    this.errorBox.classList.add('occgrid-error');
    this.errorBox.hidden = false;
  }

  clearError() {
    this.errorBox.hidden = true;
    this.errorBox.classList.remove('occgrid-error');
    this.errorBox.textContent = '';
  }

  updateJoint() {
    let r;
    try {
      r = this.core.jointPosterior(this.query);
      this.clearError();
    } catch (e) {
      this.showError(e);
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
      ', p_B = ', el('output', { class: 'doorway-trap-pb', dataset: { value: String(pb) } }, fixed(pb, 4)), '.');
    const bitsOut = (cls, x) => el('strong', { class: cls, dataset: { value: String(x) } }, fixed(x, 3));
    this.entropyOut.replaceChildren(
      'Joint entropy H(m_A, m_B) = ', bitsOut('doorway-trap-joint-entropy', r.jointEntropyBits), ' bits', el('br'),
      'Sum of the marginal entropies H(m_A) + H(m_B) = ', bitsOut('doorway-trap-marginal-entropy', r.marginalEntropySumBits), ' bits', el('br'),
      'The gap, shared information = ', bitsOut('doorway-trap-shared-information', r.sharedInformationBits), ' bits',
      el('span', { class: 'occgrid-caption' }, ' — the factored map states the sum, an upper bound on the joint’s entropy; ',
        'the gap is what knowing one cell tells about the other (their mutual information), never negative. ',
        'The sum counts those bits twice, so an explorer that scores information gain on it expects to learn more than there is to learn.'));
    this.trapOut.replaceChildren(
      '“Both free”: truly ', el('strong', { class: 'doorway-trap-free-true', dataset: { value: String(r.allFreeTrue) } }, fixed(r.allFreeTrue, 4)),
      ', factored ', el('strong', { class: 'doorway-trap-free-factored', dataset: { value: String(r.allFreeFactored) } }, fixed(r.allFreeFactored, 4)),
      ' — ', el('strong', { class: 'doorway-trap-ratio', dataset: { value: String(r.allFreeRatio) } }, `${fixed(r.allFreeRatio, r.allFreeRatio >= 10 ? 1 : 2)}×`),
      r.allFreeRatio >= 1 ? ' too likely under the product of marginals.' : ' as likely under the product of marginals.',
      el('br'),
      '“Both occupied”: truly ', el('strong', { class: 'doorway-trap-occ-true', dataset: { value: String(r.allOccupiedTrue) } }, fixed(r.allOccupiedTrue, 4)),
      ', factored ', el('strong', { class: 'doorway-trap-occ-factored', dataset: { value: String(r.allOccupiedFactored) } }, fixed(r.allOccupiedFactored, 4)),
      ` — ${fixed(r.allOccupiedRatio, 2)}×`, r.allOccupiedRatio >= 1 ? ' too likely.' : ' as likely.');
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
    const zMax = q.model.z_max;
    const z = q.readings[0];
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, W, H);
    // The cone out to z_max, with metre ticks along its lower edge.
    drawCones(ctx, 1, [{ x: ox, y: oy, heading: 0, halfWidth: half, range: zMax * scale }], { color: COLORS.evidence, fillAlpha: '1f', lineWidth: 1 });
    ctx.save();
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
      // The core's gray for the marginal (mid-gray before the first answer).
      const g = this.jointReport ? this.jointReport.marginalGrays[j] : 128;
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
    const range = Math.min(this.query.model.z_max, Math.max(this.minRange, Math.hypot(fwd, left)));
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
    const range = Math.min(this.query.model.z_max, Math.max(this.minRange, Math.round((b.range + m[0]) * 100) / 100));
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

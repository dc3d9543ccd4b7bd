// What Map Weaver's real-log panel shows of a pane mapped without the
// log's poses: a SLAM pane's pose graph drawn over its map on request (a
// "pose graph" toggle: the nodes, the local edges in one colour, the loop
// closures in another, with a legend), and the pose error against the
// log's corrected poses under the maps (the aligned absolute trajectory
// error over the scans placed so far). The core computes every position
// and figure (the session's `poseGraph` and `poseError`); this module only
// draws and words them.
import { el, fixed, toggle } from './ui.js';

export const LOCAL_COLOR = 'rgba(33, 102, 172, 0.75)';
export const LOOP_COLOR = '#e7298a';
const NODE_COLOR = 'rgba(33, 102, 172, 0.9)';

/** True when some pane of `panel` keeps a pose graph (SLAM). */
function hasGraph(panel) {
  return panel.state?.panes?.some((p) => p.poses === 'slam') ?? false;
}

/**
 * The "pose graph" toggle with its legend, hidden until a pane keeps a
 * graph; turning it on or off draws the panes again from their last views.
 */
export function poseGraphControl(panel) {
  const key = (color, text) => {
    const swatch = el('span', { class: 'map-weaver-log-swatch map-weaver-log-path', 'aria-hidden': 'true' });
    swatch.style.borderTopColor = color; // through the CSSOM: the page's policy refuses style attributes
    return el('span', { class: 'map-weaver-log-key' }, swatch, text);
  };
  const legend = el('span', { class: 'occgrid-caption map-weaver-log-graph-legend', hidden: true },
    key(LOCAL_COLOR, 'local matches'), ' ', key(LOOP_COLOR, 'loop closures'));
  const control = toggle('pose graph', false, (on) => {
    legend.hidden = !on;
    panel.redraw();
    panel.sidePanes.forEach((_, i) => panel.paintSide(i + 1));
  }, { name: 'pose-graph' });
  control.input.title = 'Draw the SLAM pose graph over its map: its nodes, the local matches and the loop closures';
  const root = el('div', { class: 'occgrid-controls map-weaver-log-graph', hidden: true }, control.root, legend);
  return { root, get on() { return control.checked && !root.hidden; } };
}

/** Segments `[u0, v0, u1, v1, …]` of `g` from float `at`, `n` of them, stroked in `color`. */
function strokeSegments(ctx, g, at, n, color, lineWidth) {
  if (n < 1) return;
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  ctx.beginPath();
  for (let i = at, end = at + 4 * n; i < end; i += 4) {
    ctx.moveTo(g[i], g[i + 1]);
    ctx.lineTo(g[i + 2], g[i + 3]);
  }
  ctx.stroke();
}

/**
 * Draws pane `k`'s pose graph on `ctx` (already in the view's image-unit
 * transform; `unit` image units per device pixel) when the toggle is on
 * and the pane keeps one: the nodes as dots, the local edges, then the
 * loop closures over them. Shows or hides the toggle as panes keep graphs.
 */
export function drawPoseGraph(ctx, panel, k, unit) {
  const control = panel.poseGraph;
  if (!control) return;
  if (k === 0) control.root.hidden = !hasGraph(panel);
  if (!control.on) return;
  const g = panel.session.poseGraph(k);
  if (!g) return;
  const [nodes, locals, loops] = g;
  ctx.save();
  ctx.lineCap = 'round';
  strokeSegments(ctx, g, 3 + 2 * nodes, locals, LOCAL_COLOR, unit);
  ctx.fillStyle = NODE_COLOR;
  const r = 1.5 * unit;
  for (let i = 3, end = 3 + 2 * nodes; i < end; i += 2) ctx.fillRect(g[i] - r, g[i + 1] - r, 2 * r, 2 * r);
  strokeSegments(ctx, g, 3 + 2 * nodes + 4 * locals, loops, LOOP_COLOR, 1.25 * unit);
  ctx.restore();
}

/**
 * The pose error of the operated pane under the maps, when the log has
 * corrected poses and the pane is not at them: the aligned ATE over the
 * scans placed so far and the last scan's error (the core counts a
 * bounded number of scans a call, so a long log's figure catches up over
 * a few drawings). Removed otherwise.
 */
export function showPoseError(panel) {
  let line = panel.root.querySelector('.map-weaver-log-pose-error');
  const figures = panel.session?.poseError(0);
  if (!figures) {
    line?.remove();
    return;
  }
  if (!line) {
    line = el('p', { class: 'map-weaver-log-pose-error occgrid-readout', 'aria-live': 'off' });
    panel.stage.after(line);
  }
  const [scans, placed, ateM, scanErrorM] = figures;
  const e = { scans, placed, ateM, scanErrorM };
  const n = (x) => x.toLocaleString('en-US');
  const over = e.scans < e.placed ? `the first ${n(e.scans)} of ${n(e.placed)} scans` : `${n(e.scans)} scans`;
  line.textContent = `Pose error against the log’s corrected poses: ${fixed(e.ateM, 3)} m RMS over ${over} ` +
    `after the best rigid alignment (absolute trajectory error); scan ${n(e.scans)} is ${fixed(e.scanErrorM, 3)} m off.`;
  Object.assign(line.dataset, { ateM: String(e.ateM), scans: String(e.scans), placed: String(e.placed), scanErrorM: String(e.scanErrorM) });
}

// The views of Map Weaver's real-log panel drawn on its canvases: each
// pane's view drawn by the core a band of rows per task (the picture on
// screen stays until the new one is whole), then painted with the laser's
// path, the robot, the scan match, the pose graph (on request) and the
// keyboard cursor over it, and the pose error under the maps. The
// core computes every pixel of the map (`renderViewWithin`); this module
// only sequences the calls and draws the overlays.
import { drawMapImage, drawPath, drawRobot, outlineCell } from './layers.js';
import { drawMatch, livePath } from './log-match.js';
import { drawPoseGraph, showPoseError } from './pose-graph-layer.js';

/** Map cells sampled per drawing call: a view is drawn in bands of rows (the zoomed-out campus samples 17 M cells in a 1200 × 900 view, 45 ms in one call). */
const VIEW_BAND_SAMPLES = 2_000_000;
const PATH_COLOR = 'rgba(26, 152, 80, 0.55)';
const ROBOT_COLOR = '#1a9850';
const CURSOR_COLOR = '#2c7bb6';

/** Device pixels per CSS pixel of `canvas`. */
export const dpr = (canvas) => canvas.width / Math.max(1, canvas.clientWidth || canvas.width);

/**
 * Draws `panel`'s operated map, its counts (`finished`), each map beside
 * it: a view a band of rows per task, the counts a task of their own (the
 * panel's `pause` ends each task; each call is timed in its trace); false
 * if the panel went away.
 */
export async function drawViews(panel, finished = true) {
  panel.redrawMs = 0;
  const quick = !finished && panel.state?.state === 'building';
  const sides = panel.sidePanes.flatMap((side, i) => (side.geometry && !side.figure.hidden ? [i + 1] : []));
  for (const k of [0, ...(finished ? ['counts'] : []), ...sides]) {
    for (let whole = false; !whole;) {
      await panel.pause();
      if (panel.disposed || !panel.session) return false;
      const t1 = performance.now();
      whole = k === 'counts' ? (panel.draw(false), true) : drawBand(panel, k, quick);
      panel.trace.push(['draw', performance.now() - t1]);
      panel.redrawMs += panel.trace.at(-1)[1];
      if (whole === null) return false;
    }
  }
  return true;
}

/** One band of pane `k`'s view (`quick`: of a map still being built), shown once whole: true then, null if the pane is gone. */
function drawBand(panel, k, quick) {
  let whole;
  try {
    whole = panel.session.renderViewWithin(k, VIEW_BAND_SAMPLES, quick);
  } catch {
    return null; // the panes changed meanwhile (another log, fewer panes)
  }
  if (whole) k === 0 ? panel.showView() : panel.paintSide(k);
  return whole;
}

/**
 * Draws pane `k`'s view `v` (`ptr` its pixels) on `canvas`, the laser's
 * path so far with the robot, the scan match, the pose graph (when asked
 * for) and `cursor` (if any),
 * through the view's transform, their widths in screen pixels at any zoom.
 */
export function paintPane(panel, canvas, k, ptr, v, path, cursor = null) {
  drawMapImage(canvas, panel.memory, ptr, v.width, v.height);
  const ctx = canvas.getContext('2d');
  ctx.save();
  ctx.setTransform(v.scale, 0, 0, v.scale, -v.u0 * v.scale, -v.v0 * v.scale);
  const unit = dpr(canvas) / v.scale;
  const done = panel.state?.panes[k]?.scansDone ?? 0;
  if (path && done >= 1) {
    drawPath(ctx, 1, livePath(panel, k, path), done, { color: PATH_COLOR, lineWidth: unit });
    drawRobot(ctx, 1, panel.session.robotAt(k, done - 1), {
      color: ROBOT_COLOR, radius: 4 * unit, tick: 10 * unit, lineWidth: 1.5 * unit,
    });
  }
  drawMatch(ctx, panel, k, unit);
  drawPoseGraph(ctx, panel, k, unit);
  if (k === 0) showPoseError(panel);
  if (cursor) outlineCell(ctx, 1, cursor, { color: CURSOR_COLOR, lineWidth: 2 * unit, pad: 2 * unit });
  ctx.restore();
}

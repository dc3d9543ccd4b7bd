// The scan-matched pose source in Map Weaver's real-log panel: the matched
// path as it grows, and the current scan's match drawn over its pane while the map builds (the scan's returns where
// the match put them, and the robot where the odometry predicted it), with
// a line of figures under the pane. The core computes every number (the
// session's `matchView`); this module only draws and words them.
import { el, fixed } from './ui.js';
import { drawRobot } from './layers.js';
import { grownPath } from './log-path.js';

const MATCHED = 'scan-matched';
const POINT_COLOR = '#d95f02';
const REFUSED_COLOR = '#7570b3';
const PREDICTED_COLOR = 'rgba(90, 90, 90, 0.9)';

/** True when pane `k` of `state` is scan-matched. */
function matched(state, k) {
  return state?.panes?.[k]?.poses === MATCHED;
}

/**
 * The path to draw on pane `k`: a scan-matched pane's poses are found as
 * its scans are matched, so its path grows at each drawing by the scans
 * matched since the last; a SLAM pane's poses also move when its graph is
 * optimised, so its path is read again whole; any other pane's (`path`,
 * read once at layout) stays.
 */
export function livePath(panel, k, path) {
  if (panel.state?.panes?.[k]?.poses === 'slam') return panel.session.pathPixels(k);
  if (!matched(panel.state, k)) return path;
  return grownPath(panel.session, k, path, panel.state.panes[k].scansDone);
}

/** Square dots of half-width `r` at the flat `[u0, v0, u1, v1, …]` points. */
function drawPoints(ctx, points, color, r) {
  ctx.save();
  ctx.fillStyle = color;
  for (let i = 0; i + 1 < points.length; i += 2) ctx.fillRect(points[i] - r, points[i + 1] - r, 2 * r, 2 * r);
  ctx.restore();
}

/**
 * The line of figures of a scan-matched pane, made when first needed: under
 * the maps (beside the stage, so that the three maps keep their row).
 */
function figuresLine(panel) {
  let line = panel.root.querySelector('.map-weaver-log-match');
  if (!line) {
    line = el('p', { class: 'map-weaver-log-match occgrid-readout', 'aria-live': 'off' });
    panel.stage.after(line);
  }
  return line;
}

/**
 * Draws scan-matched pane `k`'s current match on `ctx` (already in the
 * view's image-unit transform; `unit` image units per device pixel) while
 * its map builds: the matched scan's returns at the pose found (orange when
 * the match was trusted, violet when the scan was put at its prediction),
 * and the robot where the odometry predicted it (gray). Once the map is
 * finished only the figures of the last match stay. Nothing for another
 * pane.
 */
export function drawMatch(ctx, panel, k, unit) {
  if (!matched(panel.state, k)) {
    if (k === 0) panel.root.querySelector('.map-weaver-log-match')?.remove();
    return;
  }
  const line = figuresLine(panel);
  const m = panel.session.matchView(k);
  if (!m) {
    if (line) line.textContent = '';
    return;
  }
  const building = !panel.state.panes[k].finished;
  if (building) {
    drawRobot(ctx, 1, m.predicted, { color: PREDICTED_COLOR, radius: 4 * unit, tick: 10 * unit, lineWidth: 1.5 * unit });
    drawPoints(ctx, m.points, m.accepted ? POINT_COLOR : REFUSED_COLOR, 1.6 * unit);
  }
  {
    const how = m.accepted
      ? `matched: moved ${fixed(m.correctionM * 100, 1)} cm and ${fixed(m.correctionDeg, 2)}° from the odometry’s prediction`
      : 'not trusted (too little of the scan on measured cells, or too weak a fit): put at the odometry’s prediction';
    line.textContent = `scan ${m.scan.toLocaleString('en-US')} ${how}; match score ${fixed(m.score, 2)} ` +
      `(${fixed(m.predictedScore, 2)} at the prediction), ${fixed(m.overlap * 100, 0)}% of its returns on measured cells.`;
    Object.assign(line.dataset, { scan: String(m.scan), accepted: String(m.accepted), building: String(building) });
  }
}

// Map Weaver's readouts of the two maps against each other (exercises 6
// and 8), shown in one line under the maps: the text is the words module's,
// every number the core's (`readout().difference`, `readout().l0Drift`),
// and the same numbers go into the line's data attributes for scripts.
// Rewritten every frame while the lap plays, each text is set only when its
// words change (ui.js setText).
import { fixed, setText } from './ui.js';
import {
  comparisonText, MODEL_NAMES, POSE_NAMES, MAPPER_NAMES, SPOKEN_MODELS, SPOKEN_POSES, CURSOR_HINT, count, ghostText, bits,
} from './map-weaver-words.js';

/** Shows what the core's readout `r` says about the two maps in `line` (hidden when nothing). */
export function showComparison(line, r) {
  const text = comparisonText(r);
  setText(line, text);
  if (line.hidden !== !text) line.hidden = !text;
  Object.assign(line.dataset, {
    cellsDiffer: String(r.difference?.cells ?? ''),
    cellsOf: String(r.difference?.of ?? ''),
    drift: String(r.l0Drift?.perUpdate ?? ''),
    modelL0: String(r.l0Drift?.modelL0 ?? ''),
  });
}

/**
 * Shows pane readout `pr` (of the core's readout `r`) in pane `p`: its
 * settings line, figures, data attributes and the map's text alternative.
 * `behind`: scans the pane's rebuild still owes; while it is under way the
 * data attributes keep describing the last finished map.
 */
export function showPaneReadout(p, pr, r, behind) {
  const sensor = pr.sensor === 'cone' ? `${fixed(pr.betaDeg, 0)}° cone` : 'LiDAR';
  setText(p.note, `· ${MODEL_NAMES[pr.model]}, ${POSE_NAMES[pr.pose]} · ${MAPPER_NAMES[pr.mapper]}, ${sensor}, ` +
    `${pr.beams} beams, ${fixed(pr.resolution, 2)} m${pr.forgetL0 ? ' · l0 not subtracted' : ''}`);
  setText(p.scanMs, pr.scanMs === null || pr.scanMs === undefined ? '–' : fixed(pr.scanMs, 2));
  setText(p.ghost, ghostText(pr.ghost));
  p.root.dataset.behind = String(behind);
  setText(p.entropy, bits(pr.entropyBits));
  setText(p.brier, fixed(pr.brier, 4));
  setText(p.visited, count(pr.cellsVisited));
  // The data attributes describe a finished map: while a knob's
  // rebuild is under way they keep the last one's.
  if (behind > 0) return;
  Object.assign(p.root.dataset, {
    mapper: pr.mapper, sensor: pr.sensor, betaDeg: String(pr.betaDeg), beams: String(pr.beams),
    resolution: String(pr.resolution), forgetL0: String(pr.forgetL0), cellsVisited: String(pr.cellsVisited),
    scanMs: String(pr.scanMs ?? ''), ghostFaded: String(pr.ghost.faded), ghostLongest: String(pr.ghost.longestScans ?? ''),
    ghostLongestSeconds: String(pr.ghost.longestSeconds ?? ''), ghostRecursionSeconds: String(pr.ghost.recursionSeconds ?? ''),
    clamp: String(pr.clamp), strength: String(pr.strength),
  });
  p.root.dataset.entropy = String(pr.entropyBits);
  p.root.dataset.brier = String(pr.brier);
  p.root.dataset.model = pr.model;
  p.root.dataset.pose = pr.pose;
  setText(p.canvas,
    `${p.side === 'left' ? 'Left' : 'Right'} map: ${SPOKEN_MODELS[pr.model]} ${SPOKEN_POSES[pr.pose]}, after ${count(r.scans)} ` +
    `scan${r.scans === 1 ? '' : 's'}: entropy ${bits(pr.entropyBits)} bits, Brier score ${fixed(pr.brier, 4)}. ${CURSOR_HINT}`, 'aria-label');
}

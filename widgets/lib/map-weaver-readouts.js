// Map Weaver's readouts of the two maps against each other (exercises 6
// and 8), shown in one line under the maps: the text is the words module's,
// every number the core's (`readout().difference`, `readout().l0Drift`),
// and the same numbers go into the line's data attributes for scripts.
import { comparisonText } from './map-weaver-words.js';

/** Shows what the core's readout `r` says about the two maps in `line` (hidden when nothing). */
export function showComparison(line, r) {
  line.textContent = comparisonText(r);
  line.hidden = !line.textContent;
  Object.assign(line.dataset, {
    cellsDiffer: String(r.difference?.cells ?? ''),
    cellsOf: String(r.difference?.of ?? ''),
    drift: String(r.l0Drift?.perUpdate ?? ''),
    modelL0: String(r.l0Drift?.modelL0 ?? ''),
  });
}

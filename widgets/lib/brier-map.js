// Map Weaver's per-cell Brier difference (exercise 8): where each of the two
// maps is closer to the ground truth, under the maps on request. The core
// draws the image (`MapWeaver.brierPixels`), counts the cells
// (`readout().brierDifference`) and names the colours
// (`constants().mapWeaver.brierColours`); this layer shows them.
import { el, hiDpiCanvas, setText, toggle } from './ui.js';
import { drawMapImage } from './layers.js';
import { count, signed } from './map-weaver-words.js';

const rgb = (c) => `rgb(${c.join(', ')})`;
/** A legend's colour square (styled through the CSSOM: the page's policy refuses inline style attributes). */
function swatch(colour) {
  const s = el('span', { class: 'map-weaver-swatch', 'aria-hidden': 'true' });
  s.style.background = colour;
  return s;
}

/**
 * The view: a switch, and under it the image, its counts and its legend.
 * `onToggle(on)` is called when the reader flips the switch.
 */
export function brierMap(onToggle) {
  const canvas = el('canvas', { class: 'map-weaver-brier-map-canvas', role: 'img', 'aria-label': 'Per-cell Brier difference: not drawn yet.' });
  const counts = el('p', { class: 'occgrid-readout map-weaver-brier-map-counts' }, '');
  const legend = el('p', { class: 'occgrid-caption map-weaver-brier-map-legend' });
  const box = el('div', { class: 'map-weaver-brier-map-box', hidden: true }, canvas, counts, legend);
  const toggler = toggle('Show where each map is closer to the truth (per-cell Brier difference)', false, (on) => onToggle(on), { name: 'brier-map' });
  toggler.root.dataset.controls = 'toggles';
  const root = el('div', { class: 'map-weaver-brier-map' }, toggler.root, box);
  let shown = '';
  let legendOf = null;
  return {
    root,
    canvas,
    /** Shows (`on`) or hides the view, as the switch or the attribute says. */
    set(on) {
      toggler.input.checked = on;
      box.hidden = !on;
      shown = '';
    },
    get on() {
      return toggler.input.checked;
    },
    /**
     * Draws the view from the core's readout `r` at `cssWidth` CSS pixels
     * wide; `colours` is `constants().mapWeaver.brierColours`. Hidden
     * whole when the two maps do not share their cells.
     */
    draw(weaver, memory, r, cssWidth, colours, force = false) {
      const d = r.brierDifference;
      root.hidden = !d;
      if (!d || box.hidden) return;
      if (legendOf !== colours) {
        legendOf = colours;
        legend.replaceChildren(
          swatch(rgb(colours.leftCloser)), ' left map closer to the truth · ',
          swatch(rgb(colours.rightCloser)), ' right map closer · ',
          swatch('#fff'), ' alike (', swatch(rgb(colours.alikeOccupied)), ' on the apartment’s walls and furniture) · ',
          swatch(rgb(colours.notScored)), ' outside the surveyed rooms (not scored). The deeper the colour, the larger the gap in (p − truth)².');
      }
      const [w, h] = weaver.paneSize(0);
      const key = JSON.stringify([r.scans, w, h, cssWidth, d]);
      if (!force && key === shown) return;
      shown = key;
      if (canvas.dataset.css !== `${cssWidth}x${w}x${h}`) {
        canvas.dataset.css = `${cssWidth}x${w}x${h}`;
        hiDpiCanvas(canvas, cssWidth, Math.round((cssWidth * h) / w));
      }
      const ptr = weaver.brierPixels();
      if (ptr) drawMapImage(canvas, memory, ptr, w, h);
      const text = `Right map’s Brier score minus the left’s: ${signed(d.mean, 4)}, the mean over ${count(d.region)} surveyed cells of each cell’s ` +
        `(p − truth)² in the right map minus the left’s. The left map is closer to the truth in ${count(d.leftCloser)} cells, ` +
        `the right in ${count(d.rightCloser)}; ${count(d.tied)} score alike.`;
      setText(counts, text);
      setText(canvas, `Per-cell Brier difference after ${count(r.scans)} scans. ${text}`, 'aria-label');
      Object.assign(root.dataset, {
        mean: String(d.mean), leftCloser: String(d.leftCloser), rightCloser: String(d.rightCloser), tied: String(d.tied), region: String(d.region),
      });
    },
  };
}

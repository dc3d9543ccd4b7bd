// One map pane, as every map widget has it: a canvas sized to its column
// (hi-DPI, never wider than the widget's `map-width`), a pointer or the
// arrow keys pointing at one cell of the drawn image, and an "Export map"
// button that saves the pane's map for ROS. Positions here are IMAGE UNITS:
// x right, y down, origin at the top-left of the map image, one unit per
// cell of the drawn image (widgets/lib/layers.js draws in the same units).
import { MAX_ANIMATED_CANVAS_PIXELS, button, hiDpiCanvas, showError, smallScreen, trackVisibility } from './ui.js';
import { downloadMapPair } from './export.js';

/** Narrowest map, CSS pixels: below it a cell is too small to point at. */
const MIN_CSS_WIDTH = 120;

/**
 * Sizes each pane's canvas to its column for a `imageW x imageH` map: as
 * wide as the pane (`fallback` CSS pixels before it has a width), between
 * MIN_CSS_WIDTH and `widest`, the height keeping the map's aspect. A pane
 * whose width did not change keeps its canvas (and its drawing). A pane is
 * redrawn every frame while its widget plays: on a phone its backing store
 * keeps to MAX_ANIMATED_CANVAS_PIXELS. Sets `pane.cssW` and `pane.ctx`; set
 * `pane.cssW = 0` to force a resize.
 */
export function sizePanes(panes, imageW, imageH, widest, fallback = 320) {
  for (const p of panes) {
    const cssW = Math.max(MIN_CSS_WIDTH, Math.min(widest, Math.floor(p.root.clientWidth || fallback)));
    if (p.cssW === cssW) continue;
    p.cssW = cssW;
    p.ctx = hiDpiCanvas(p.canvas, cssW, Math.round((cssW * imageH) / imageW), { maxPixels: smallScreen() ? MAX_ANIMATED_CANVAS_PIXELS : Infinity });
  }
}

/**
 * Keeps `pane.onScreen` for each pane (true until the first report) and
 * calls `onShow(pane)` when one comes back on screen: on a phone a widget's
 * panes are stacked, and one playing redraws only those a reader can see,
 * each of the others once it scrolls back into view.
 */
export function followPaneVisibility(panes, onShow) {
  for (const p of panes) {
    p.onScreen = true;
    trackVisibility(p.root, (visible) => {
      const back = visible && !p.onScreen;
      p.onScreen = visible;
      if (back) onShow(p);
    });
  }
}

/** Forgets every pane's size, so that the next `sizePanes` resizes them all. */
export function resetPaneSizes(panes) {
  for (const p of panes) p.cssW = 0;
}

/** Calls `onResize` whenever `element` (the row of panes) changes size. */
export function followResize(element, onResize) {
  if (!('ResizeObserver' in window)) return null;
  const observer = new ResizeObserver(() => onResize());
  observer.observe(element);
  return observer;
}

/**
 * The image cell under a pointer event on `canvas`, whose drawn map is
 * `imageW x imageH` cells: `{ col, row }` in image units (may lie outside
 * the image when the pointer is on the canvas's edge).
 */
export function pointerCell(canvas, ev, imageW, imageH) {
  const rect = canvas.getBoundingClientRect();
  return {
    col: Math.floor(((ev.clientX - rect.left) / rect.width) * imageW),
    row: Math.floor(((ev.clientY - rect.top) / rect.height) * imageH),
  };
}

/** Arrow keys as steps in image units (down is +row). */
const ARROWS = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };

/**
 * The cell the arrow key of `ev` moves `from` to (`k` cells at a time),
 * kept inside the `imageW x imageH` image; null for any other key. The
 * caller prevents the key's default (page scrolling) when it acts on it.
 */
export function arrowCell(ev, from, imageW, imageH, k = 1) {
  const m = ARROWS[ev.key];
  if (!m) return null;
  return {
    col: Math.max(0, Math.min(imageW - 1, from.col + k * m[0])),
    row: Math.max(0, Math.min(imageH - 1, from.row + k * m[1])),
  };
}

/**
 * The "Export map" button of a pane. `spoken` completes its accessible
 * name, "Export map (spoken)", which starts with the visible text (WCAG
 * 2.5.3); `title` describes it.
 */
export function exportButton({ name, title, spoken, onClick }) {
  const b = button('Export map', onClick, { name, title });
  b.setAttribute('aria-label', `Export map (${spoken})`);
  return b;
}

/**
 * Saves a map as a ROS map_server pair in one zip named after `stem`:
 * `makePair()` asks the core for `{ pgm, yaml }`. A failure is shown in
 * `errorHost`, after `context`.
 */
export async function exportMap(errorHost, stem, makePair, context = '') {
  try {
    await downloadMapPair(stem, makePair());
  } catch (e) {
    showError(errorHost, e, context);
  }
}

// Pointing at one cell of a map canvas, the same way with a mouse, a pen,
// a finger or the keyboard. A tap fires no pointermove, only pointerdown;
// a lifted finger fires pointerleave at once; and a tap focuses the canvas,
// whose keyboard cursor must not then replace the tapped cell. So: a press
// or a move reads the cell under it, only a mouse leaving the map clears
// the readout (a finger's cell stays on screen to be read), and only
// keyboard focus (`:focus-visible`) places the keyboard cursor.

/**
 * Wires `canvas` for pointing: `point(event)` on every press or move,
 * `leave()` when a mouse leaves the map, `keyboardFocus()` when the
 * keyboard (not a press) focuses it.
 */
export function followCellPointer(canvas, { point, leave, keyboardFocus }) {
  canvas.addEventListener('pointerdown', (e) => point(e));
  canvas.addEventListener('pointermove', (e) => point(e));
  canvas.addEventListener('pointerleave', (e) => {
    if (e.pointerType === 'mouse') leave();
  });
  canvas.addEventListener('focus', () => {
    if (canvas.matches(':focus-visible')) keyboardFocus();
  });
}

/**
 * Puts the cell readout `readout` over the map `stage` (a positioned box
 * around the canvas), on the half away from the pointed `row` of a map
 * `height` rows tall, so that it never hides the cell it reads; and within
 * the part of the map inside the window, so that a map taller than the
 * window, or scrolled partly off it, still shows the readout on screen.
 */
export function placeReadout(readout, stage, row, height) {
  if (readout.parentElement !== stage) stage.append(readout);
  readout.hidden = false;
  const box = stage.getBoundingClientRect();
  const seenTop = Math.max(0, -box.top);
  const seenBottom = Math.max(seenTop, Math.min(box.height, window.innerHeight - box.top));
  const y = ((row + 0.5) / Math.max(1, height)) * box.height;
  const below = y < (seenTop + seenBottom) / 2;
  readout.dataset.at = below ? 'bottom' : 'top';
  const top = below ? seenBottom - readout.offsetHeight : seenTop;
  readout.style.top = `${Math.max(0, Math.min(top, box.height - readout.offsetHeight))}px`;
}

/**
 * A cell readout that floats over a map (see `placeReadout`): a copy of the
 * readout line below the figure, which screen readers already hear.
 */
export function floatingReadout() {
  const p = document.createElement('p');
  p.className = 'occgrid-readout occgrid-floating-readout';
  p.setAttribute('aria-hidden', 'true');
  p.hidden = true;
  return p;
}

/** Wraps `canvas` in a positioned box over which a floating readout is placed. */
export function mapStage(canvas) {
  const stage = document.createElement('div');
  stage.className = 'occgrid-map-stage';
  stage.append(canvas);
  return stage;
}

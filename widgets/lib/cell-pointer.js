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
 * `height` rows tall, so that it never hides the cell it reads.
 */
export function placeReadout(readout, stage, row, height) {
  if (readout.parentElement !== stage) stage.append(readout);
  readout.dataset.at = row < height / 2 ? 'bottom' : 'top';
  readout.hidden = false;
}

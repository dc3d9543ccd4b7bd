// The drawing layers the map widgets compose: the map image, beams and their
// hits, sonar cones, the robot with its heading, outlined cells (cursor,
// hover, tracked and flipped cells) and outlined boxes (walls, person, a
// table's footprint). Each widget stacks the layers it needs on a pane
// (`layerStack`), each layer redrawing itself from the frame it is given.
//
// Every position is in IMAGE UNITS: x right, y down, origin at the top-left
// of the map image, one unit per cell of the drawn image. Angles are image
// angles: radians from +x, turning towards +y (clockwise on screen). `s` is
// canvas units per image unit (CSS pixels per cell on a hi-DPI pane, 1 on a
// canvas the size of its image). Nothing here computes a model value.

const offscreen = new WeakMap();

/**
 * Draws a `w x h` RGBA image that lives in wasm memory at `ptr` onto the
 * whole canvas, scaled with crisp pixels. The view is made on each call, so
 * it never outlives a growth of the wasm memory.
 */
export function drawMapImage(canvas, memory, ptr, w, h) {
  let off = offscreen.get(canvas);
  if (!off || off.width !== w || off.height !== h) {
    off = document.createElement('canvas');
    off.width = w;
    off.height = h;
    offscreen.set(canvas, off);
  }
  const view = new Uint8ClampedArray(memory.buffer, ptr, w * h * 4);
  off.getContext('2d').putImageData(new ImageData(view, w, h), 0, 0);
  const ctx = canvas.getContext('2d');
  ctx.save();
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(off, 0, 0, canvas.width, canvas.height);
  ctx.restore();
}

/**
 * A pane's layers, drawn in the order they were added: `add(layer)` with
 * `layer(frame)`, `draw(frame)` redraws them all. The frame carries the
 * context, the scale and whatever the widget's layers read.
 */
export function layerStack() {
  const layers = [];
  return {
    add(layer) {
      layers.push(layer);
      return layer;
    },
    draw(frame) {
      for (const layer of layers) layer(frame);
    },
  };
}

/** Beams: a line from `from` ([x, y]) to each of the `count` ends in `ends` ([x0, y0, x1, y1, …]). */
export function drawBeams(ctx, s, from, ends, { color, lineWidth = 1, count = ends.length >> 1 } = {}) {
  ctx.save();
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  ctx.beginPath();
  for (let i = 0; i < count; i++) {
    ctx.moveTo(from[0] * s, from[1] * s);
    ctx.lineTo(ends[2 * i] * s, ends[2 * i + 1] * s);
  }
  ctx.stroke();
  ctx.restore();
}

/** A small square at each end of `ends` whose flag in `hits` is set (`size` canvas units). */
export function drawHits(ctx, s, ends, hits, { color, size = 3 } = {}) {
  ctx.save();
  ctx.fillStyle = color;
  for (let i = 0; i < hits.length; i++) {
    if (hits[i]) ctx.fillRect(ends[2 * i] * s - size / 2, ends[2 * i + 1] * s - size / 2, size, size);
  }
  ctx.restore();
}

/**
 * Sonar cones, each `{ x, y, heading, halfWidth, range }` (apex, axis and
 * half-width as image angles, range in image units), filled with `color`
 * at `fillAlpha` (two hex digits; null: no fill). `outline` 'sector'
 * strokes the whole wedge, 'arc' only its far arc; `dashed` dashes it.
 */
export function drawCones(ctx, s, cones, { color, fillAlpha = '26', outline = 'sector', dashed = false, lineWidth = 1.25 } = {}) {
  ctx.save();
  if (dashed) ctx.setLineDash([4, 3]);
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  if (fillAlpha !== null) ctx.fillStyle = color + fillAlpha;
  for (const c of cones) {
    const x = c.x * s;
    const y = c.y * s;
    const r = c.range * s;
    const a0 = c.heading - c.halfWidth;
    const a1 = c.heading + c.halfWidth;
    ctx.beginPath();
    ctx.moveTo(x, y);
    ctx.arc(x, y, r, a0, a1);
    ctx.closePath();
    if (fillAlpha !== null) ctx.fill();
    if (outline === 'arc') {
      ctx.beginPath();
      ctx.arc(x, y, r, a0, a1);
    }
    ctx.stroke();
  }
  ctx.restore();
}

/**
 * The robot: a dot at `{ x, y }` and a tick `tick` canvas units long along
 * its `heading` (an image angle); with `truth` ({ x, y }), first a ring
 * where it truly is.
 */
export function drawRobot(ctx, s, { x, y, heading }, { color, radius = 4, tick = 10, lineWidth = 2, truth = null, ringRadius = 6, ringWidth = 1.5 } = {}) {
  ctx.save();
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  if (truth) {
    ctx.lineWidth = ringWidth;
    ctx.beginPath();
    ctx.arc(truth.x * s, truth.y * s, ringRadius, 0, 2 * Math.PI);
    ctx.stroke();
  }
  const px = x * s;
  const py = y * s;
  ctx.lineWidth = lineWidth;
  ctx.beginPath();
  ctx.arc(px, py, radius, 0, 2 * Math.PI);
  ctx.fill();
  ctx.beginPath();
  ctx.moveTo(px, py);
  ctx.lineTo(px + tick * Math.cos(heading), py + tick * Math.sin(heading));
  ctx.stroke();
  ctx.restore();
}

/** Dots of `radius` canvas units at `points` ([{ x, y }]). */
export function drawDots(ctx, s, points, { color, radius }) {
  ctx.save();
  ctx.fillStyle = color;
  for (const p of points) {
    ctx.beginPath();
    ctx.arc(p.x * s, p.y * s, radius, 0, 2 * Math.PI);
    ctx.fill();
  }
  ctx.restore();
}

/**
 * Outlines the image cell `{ col, row }`, grown by `pad` canvas units on
 * each side (negative: inset). The cursor, hovered, tracked and flipped
 * cells are all drawn with it.
 */
export function outlineCell(ctx, s, { col, row }, { color, lineWidth = 2, pad = 0, dash = null } = {}) {
  ctx.save();
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  if (dash) ctx.setLineDash(dash);
  ctx.strokeRect(col * s - pad, row * s - pad, s + 2 * pad, s + 2 * pad);
  ctx.restore();
}

/**
 * A box `[x0, y0, x1, y1]` (top-left and bottom-right corners), stroked
 * in `color`, optionally dashed and filled with `color` at `fillAlpha`.
 */
export function outlineBox(ctx, s, [x0, y0, x1, y1], { color, lineWidth = 1, dash = null, fillAlpha = null } = {}) {
  ctx.save();
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  if (dash) ctx.setLineDash(dash);
  const x = x0 * s;
  const y = y0 * s;
  const w = x1 * s - x;
  const h = y1 * s - y;
  if (fillAlpha !== null) {
    ctx.fillStyle = color + fillAlpha;
    ctx.fillRect(x, y, w, h);
  }
  ctx.strokeRect(x, y, w, h);
  ctx.restore();
}

/** A polyline through the first `count` points of `points` ([x0, y0, x1, y1, …]). */
export function drawPath(ctx, s, points, count, { color, lineWidth = 1 } = {}) {
  if (count < 1) return;
  ctx.save();
  ctx.strokeStyle = color;
  ctx.lineWidth = lineWidth;
  ctx.lineJoin = 'round';
  ctx.beginPath();
  ctx.moveTo(points[0] * s, points[1] * s);
  for (let k = 1; k < count; k++) ctx.lineTo(points[2 * k] * s, points[2 * k + 1] * s);
  ctx.stroke();
  ctx.restore();
}

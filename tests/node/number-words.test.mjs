// How the widgets write numbers (widgets/lib/ui.js): `grouped` writes what
// en-US number formatting writes (thousands separators, the shortest
// decimal form rounded half away from zero, the sign of -0) without making
// a formatter, whose first construction on a page is a long task on a
// throttled phone while the widgets build (docs/BENCHMARKS.md W7). And the
// canvases' pixel budget: `canvasScale` never goes past twice the CSS size
// nor, given a budget, past its pixels, and never below one device pixel
// per CSS pixel.
import test from 'node:test';
import assert from 'node:assert/strict';
import { canvasScale, grouped, MAX_CANVAS_SCALE } from '../../widgets/lib/ui.js';

/** A fixed spread of values: ties, carries, tiny and huge magnitudes, both zeros. */
function values() {
  const out = [0, -0, 1, -1, 0.5, 1.5, 2.5, -2.5, 1.005, 0.045, 99999.995, 999.5, 9.995, -0.4, 1e-7, 123456789.125,
    1e20, 1e21, 123456789012345680000, -21905327109331354000, Number.MAX_SAFE_INTEGER];
  // A fixed linear congruential sequence, so that every run checks the same numbers.
  let seed = 12345;
  const next = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  for (let i = 0; i < 20_000; i++) {
    out.push((next() - 0.5) * 10 ** (Math.floor(next() * 30) - 8));
    out.push(Math.round(next() * 1e7) / 1000);
  }
  return out;
}

test('grouped writes what en-US number formatting writes, for 0 to 6 decimals', () => {
  for (const d of [0, 1, 2, 3, 4, 6]) {
    const intl = new Intl.NumberFormat('en-US', { minimumFractionDigits: d, maximumFractionDigits: d });
    for (const x of values()) assert.equal(grouped(x, d), intl.format(x), `grouped(${x}, ${d})`);
  }
  assert.equal(grouped(2000), '2,000');
  assert.equal(grouped(11389.4, 1), '11,389.4');
  assert.equal(grouped(NaN), 'NaN');
  assert.equal(grouped(-Infinity), '-Infinity');
});

test('grouped makes no number formatter', () => {
  const made = { n: 0 };
  const Original = Intl.NumberFormat;
  Intl.NumberFormat = function (...args) {
    made.n += 1;
    return new Original(...args);
  };
  try {
    grouped(1234567.891, 2);
    grouped(3, 0);
  } finally {
    Intl.NumberFormat = Original;
  }
  assert.equal(made.n, 0);
});

test('a canvas gets the screen ratio up to twice its CSS size, within a pixel budget, and never less than its CSS size', () => {
  assert.equal(MAX_CANVAS_SCALE, 2);
  assert.equal(canvasScale(440, 366, { ratio: 1 }), 1);
  assert.equal(canvasScale(440, 366, { ratio: 2 }), 2);
  assert.equal(canvasScale(348, 290, { ratio: 3 }), 2, 'a 3× screen gets twice the CSS size');
  const s = canvasScale(348, 290, { ratio: 3, maxPixels: 120_000 });
  assert.ok(Math.round(348 * s) * Math.round(290 * s) <= 120_000 * 1.01, `scale ${s}`);
  assert.ok(s > 1);
  assert.equal(canvasScale(1000, 1000, { ratio: 3, maxPixels: 120_000 }), 1, 'never below one device pixel per CSS pixel');
});

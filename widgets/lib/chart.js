// Charts for the widgets, drawn by uPlot (served at /vendor/uplot/). The data
// always comes from the core; these helpers only lay it out.
import uPlot from '../../vendor/uplot/uPlot.esm.js';
import { ensureStyles } from './ui.js';

ensureStyles(new URL('../../vendor/uplot/uPlot.min.css', import.meta.url).href);

/** The colour conventions of the chapter's figures. */
export const COLORS = {
  evidence: '#1a9641', // beams and evidence overlays: green
  l0: '#2c7bb6', // the l0 reference line: blue
  series: ['#1a1a1a', '#d7191c', '#7b3294', '#e66101'],
};

/**
 * Width of a y axis that fits its longest tick label (uPlot's fixed
 * default clips labels such as "20,000" into the axis title).
 */
function fitAxis(self, values, axisIdx, cycleNum) {
  const axis = self.axes[axisIdx];
  if (cycleNum > 1) return axis._size;
  let size = axis.ticks.size + axis.gap;
  const longest = (values ?? []).reduce((a, v) => (String(v).length > a.length ? String(v) : a), '');
  if (longest) {
    self.ctx.font = axis.font[0];
    size += self.ctx.measureText(longest).width / (window.devicePixelRatio || 1);
  }
  return Math.max(40, Math.ceil(size) + 4);
}

function sizeOf(container, height) {
  return { width: Math.max(160, Math.floor(container.clientWidth || 320)), height };
}

/**
 * A chart is one image to a screen reader: its container gets role="img"
 * and a label (the widget replaces it with the values in words as they
 * change), and uPlot's own canvas and legend are hidden from the
 * accessibility tree so they are not read as unnamed parts.
 */
function describe(container, plot, fallback) {
  if (!container.hasAttribute('role')) container.setAttribute('role', 'img');
  if (!container.hasAttribute('aria-label')) container.setAttribute('aria-label', fallback);
  plot.root.setAttribute('aria-hidden', 'true');
}

function followWidth(container, plot, height) {
  if (!('ResizeObserver' in window)) return;
  new ResizeObserver(() => plot.setSize(sizeOf(container, height))).observe(container);
}

/**
 * Tick steps of an axis that counts (flips, steps, scans): whole numbers
 * only, so that a short run is not labelled "2.5".
 */
export const WHOLE_INCRS = [1, 2, 5, 10, 20, 25, 50, 100, 200, 250, 500, 1000, 2000, 5000, 10000, 20000, 50000, 100000];

/**
 * A line chart. `series` is a list of `{ label, color, dash }`; `setData(x,
 * ...ys)` replaces the data; `wholeX` keeps the x ticks on whole numbers.
 * Returns `{ plot, setData }`.
 */
export function lineChart(container, { title, xLabel, yLabel, series, height = 180, yRange, wholeX = false }) {
  const x = { label: xLabel };
  if (wholeX) x.incrs = WHOLE_INCRS;
  const opts = {
    title,
    ...sizeOf(container, height),
    // A counting axis of one point still spans a whole step.
    scales: { x: wholeX ? { time: false, range: (u, lo, hi) => [Math.floor(lo ?? 0), Math.max(Math.ceil(hi ?? 1), Math.floor(lo ?? 0) + 1)] } : { time: false }, y: yRange ? { range: yRange } : {} },
    axes: [x, { label: yLabel, size: fitAxis }],
    legend: { live: false },
    cursor: { drag: { x: false, y: false } },
    series: [
      { label: xLabel },
      ...series.map((s, i) => ({
        label: s.label,
        stroke: s.color || COLORS.series[i % COLORS.series.length],
        width: s.width || 2,
        dash: s.dash,
        points: { show: false },
      })),
    ],
  };
  const empty = [[], ...series.map(() => [])];
  const plot = new uPlot(opts, empty, container);
  describe(container, plot, title || `${yLabel} against ${xLabel}: ${series.map((s) => s.label).join(', ')}`);
  followWidth(container, plot, height);
  return { plot, setData: (x, ...ys) => plot.setData([x, ...ys]) };
}

/**
 * A bar chart of labelled values (positive and negative). `setData(labels,
 * values)` replaces the bars.
 */
export function barChart(container, { title, yLabel, color = COLORS.evidence, height = 160 }) {
  let labels = [];
  const opts = {
    title,
    ...sizeOf(container, height),
    // Bars grow from zero, so the y range always includes it.
    scales: {
      x: { time: false, range: (u, lo, hi) => [lo - 0.6, hi + 0.6] },
      y: { range: (u, lo, hi) => { const a = Math.min(0, lo), b = Math.max(0, hi); return a === b ? [-1, 1] : [a - 0.05 * (b - a), b + 0.05 * (b - a)]; } },
    },
    axes: [{ values: (u, ticks) => ticks.map((t) => labels[t] ?? '') }, { label: yLabel, size: fitAxis }],
    legend: { show: false },
    cursor: { show: false },
    series: [{}, { label: yLabel, fill: color, stroke: color, paths: uPlot.paths.bars({ size: [0.7, 40] }), points: { show: false } }],
  };
  const plot = new uPlot(opts, [[], []], container);
  describe(container, plot, title || `bar chart of ${yLabel}`);
  followWidth(container, plot, height);
  return {
    plot,
    setData(newLabels, values) {
      labels = newLabels;
      plot.setData([newLabels.map((_, i) => i), values]);
    },
  };
}

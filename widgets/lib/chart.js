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

function sizeOf(container, height) {
  return { width: Math.max(160, Math.floor(container.clientWidth || 320)), height };
}

function followWidth(container, plot, height) {
  if (!('ResizeObserver' in window)) return;
  new ResizeObserver(() => plot.setSize(sizeOf(container, height))).observe(container);
}

/**
 * A line chart. `series` is a list of `{ label, color, dash }`; `setData(x,
 * ...ys)` replaces the data. Returns `{ plot, setData }`.
 */
export function lineChart(container, { title, xLabel, yLabel, series, height = 180, yRange }) {
  const opts = {
    title,
    ...sizeOf(container, height),
    scales: { x: { time: false }, y: yRange ? { range: yRange } : {} },
    axes: [{ label: xLabel }, { label: yLabel }],
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
    axes: [{ values: (u, ticks) => ticks.map((t) => labels[t] ?? '') }, { label: yLabel }],
    legend: { show: false },
    cursor: { show: false },
    series: [{}, { label: yLabel, fill: color, stroke: color, paths: uPlot.paths.bars({ size: [0.7, 40] }), points: { show: false } }],
  };
  const plot = new uPlot(opts, [[], []], container);
  followWidth(container, plot, height);
  return {
    plot,
    setData(newLabels, values) {
      labels = newLabels;
      plot.setData([newLabels.map((_, i) => i), values]);
    },
  };
}

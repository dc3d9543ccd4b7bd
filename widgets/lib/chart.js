// Charts for the widgets, drawn by uPlot (served at /vendor/uplot/). The data
// always comes from the core; these helpers only lay it out.
//
// A chart costs a layout and a first drawing when it is made, and a drawing
// per update: a chart is made only once its box nears the screen (or
// something reads its `plot`), in a task of its own, and while data pours
// in (a widget playing) it is redrawn at most MAX_REDRAWS_PER_SECOND times
// a second, and not at all while off screen, always ending on the latest
// data. Until it is made, `setData` only keeps the data.
import { ensureStyles, startTurn, trackVisibility, whenVisible } from './ui.js';

/**
 * uPlot, loaded when the first chart is asked for rather than with the
 * widgets' modules: its module is large, and loaded on its own it is
 * evaluated in a task of its own, long before the first chart nears the
 * screen (a widget's run needs the core, a far larger download, first).
 */
let uPlot = null;
let uPlotLoading = null;
function loadUPlot() {
  uPlotLoading ??= import('../../vendor/uplot/uPlot.esm.js').then((m) => {
    uPlot = m.default;
  });
  return uPlotLoading;
}

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
function label(container, fallback) {
  if (!container.hasAttribute('role')) container.setAttribute('role', 'img');
  if (!container.hasAttribute('aria-label')) container.setAttribute('aria-label', fallback);
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
 * ...ys)` replaces the data; `wholeX` keeps the x ticks on whole numbers;
 * `onMade(plot)` runs once the uPlot exists. Returns `{ plot, made,
 * setData }` (reading `plot` makes the chart if it is not made yet; null
 * while uPlot itself is still loading).
 */
export function lineChart(container, { title, xLabel, yLabel, series, height = 180, yRange, wholeX = false, onMade }) {
  const x = { label: xLabel };
  if (wholeX) x.incrs = WHOLE_INCRS;
  // Made with the chart: its size asks for a layout.
  const opts = () => ({
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
  });
  const chart = lazyChart(container, height, (data) => new uPlot(opts(), data, container), [[], ...series.map(() => [])], onMade);
  label(container, title || `${yLabel} against ${xLabel}: ${series.map((s) => s.label).join(', ')}`);
  return { get plot() { return chart.plot; }, get made() { return chart.made; }, setData: (x, ...ys) => chart.setData([x, ...ys]) };
}

/**
 * A bar chart of labelled values (positive and negative). `setData(labels,
 * values)` replaces the bars; `yRange(u, lo, hi)` replaces the default
 * range (always holding zero); `onMade(plot)` as for `lineChart`.
 */
export function barChart(container, { title, yLabel, color = COLORS.evidence, height = 160, yRange, onMade }) {
  let labels = [];
  const opts = () => ({
    title,
    ...sizeOf(container, height),
    // Bars grow from zero, so the y range always includes it.
    scales: {
      x: { time: false, range: (u, lo, hi) => [lo - 0.6, hi + 0.6] },
      y: { range: yRange ?? ((u, lo, hi) => { const a = Math.min(0, lo), b = Math.max(0, hi); return a === b ? [-1, 1] : [a - 0.05 * (b - a), b + 0.05 * (b - a)]; }) },
    },
    axes: [{ values: (u, ticks) => ticks.map((t) => labels[t] ?? '') }, { label: yLabel, size: fitAxis }],
    legend: { show: false },
    cursor: { show: false },
    series: [{}, { label: yLabel, fill: color, stroke: color, paths: uPlot.paths.bars({ size: [0.7, 40] }), points: { show: false } }],
  });
  const chart = lazyChart(container, height, (data) => new uPlot(opts(), data, container), [[], []], onMade);
  label(container, title || `bar chart of ${yLabel}`);
  return {
    get plot() { return chart.plot; },
    get made() { return chart.made; },
    setData(newLabels, values) {
      labels = newLabels;
      chart.setData([newLabels.map((_, i) => i), values]);
    },
  };
}

/**
 * Most redraws of one chart per second while its data keeps changing: a
 * chart is a canvas at the screen's full pixel ratio (uPlot's), three times
 * a phone pane's pixels, and a curve growing by a dozen points a second
 * reads as smoothly at five redraws.
 */
export const MAX_REDRAWS_PER_SECOND = 5;

/**
 * A uPlot made by `make(data)` when `container` first nears the screen, in a
 * task of its own once uPlot has loaded (or at once when `plot` is read
 * after that), with the latest data
 * given to `setData`, redrawn at most MAX_REDRAWS_PER_SECOND times a second
 * and only while on screen (brought up to date when it comes back).
 * Reading `plot` brings it up to date first, so that what a reader (or a
 * test) reads from it is the latest data.
 */
function lazyChart(container, height, make, empty, onMade) {
  // A failure shows when the chart is made (whenVisible below).
  loadUPlot().catch(() => {});
  let plot = null;
  let latest = empty;
  let drawn = true;
  let lastDraw = -Infinity;
  let timer = 0;
  let onScreen = false;
  const materialize = () => {
    if (!plot && uPlot) {
      plot = make(latest);
      drawn = true;
      lastDraw = performance.now();
      plot.root.setAttribute('aria-hidden', 'true');
      followWidth(container, plot, height);
      trackVisibility(container, (visible) => {
        onScreen = visible;
        if (visible) schedule();
      });
      onMade?.(plot);
    }
    return plot;
  };
  const redraw = () => {
    timer = 0;
    if (!plot || drawn) return;
    drawn = true;
    lastDraw = performance.now();
    plot.setData(latest);
  };
  /** Redraws now or once the rate allows, if on screen and behind. */
  const schedule = () => {
    if (!plot || drawn || timer || !onScreen) return;
    const wait = lastDraw + 1000 / MAX_REDRAWS_PER_SECOND - performance.now();
    if (wait <= 0) redraw();
    else timer = setTimeout(redraw, wait);
  };
  whenVisible(container, () => loadUPlot().then(startTurn).then(materialize), { ahead: true });
  return {
    get made() { return plot !== null; },
    get plot() {
      loadUPlot();
      materialize();
      // uPlot lays a chart out in a microtask after its data changes: a
      // reader gets it laid out on the latest data at once.
      plot?.batch(() => redraw());
      return plot;
    },
    setData(data) {
      latest = data;
      drawn = false;
      schedule();
    },
  };
}

// <occgrid-map-weaver>'s charts: the two maps' entropy over time and each
// map's three tracked cells' log odds over time, drawn from the core's
// curves (one point per scan, at the scene's scan rate).
import { lineChart, COLORS } from './chart.js';
import { fixed } from './ui.js';
import { bits, signed } from './map-weaver-words.js';

/** The tracked cells: a wall cell, a corridor floor cell, a closet cell. */
export const TRACK_COLORS = [COLORS.series[2], COLORS.series[3], '#8c510a'];

/** The most points a curve is drawn with. */
const MAX_POINTS = 1200;

/** Makes the charts of widget `w` (once). */
export function makeCharts(w) {
  if (w.entropyChart) return;
  w.entropyChart = lineChart(w.entropyBox, {
    title: 'Map entropy over time (bits)', xLabel: 'time (s)', yLabel: 'bits', height: 210,
    series: [
      { label: 'left map', color: COLORS.series[0] },
      { label: 'right map', color: COLORS.series[1], dash: [6, 3] },
    ],
  });
  const names = w.tracked[0].map((t) => t.name);
  for (const p of w.panes) {
    p.chart = lineChart(p.chartBox, {
      title: `${p.side === 'left' ? 'Left' : 'Right'} map: three cells’ log odds`, xLabel: 'time (s)', yLabel: 'log odds', height: 230,
      // Symmetric about 0, so "up" is occupied and "down" free at a glance.
      yRange: (u, lo, hi) => {
        const m = 1.08 * Math.max(2, Math.abs(lo ?? 0), Math.abs(hi ?? 0));
        return [-m, m];
      },
      series: [
        ...names.map((name, i) => ({ label: name, color: TRACK_COLORS[i], width: i === 2 ? 3 : 2 })),
        { label: 'l0 (prior)', color: COLORS.l0, dash: [5, 4], width: 1.5 },
      ],
    });
  }
}

/** Draws the charts of widget `w` from the core's curves and readout `r`. */
export function drawCharts(w, r) {
  if (!w.entropyChart) return;
  // The time of each point comes from the core, at the scene's scan rate.
  const times = w.weaver.curveTimes();
  // A chart is a few hundred pixels wide: past MAX_POINTS scans it draws
  // every k-th point (and always the last), so that twenty laps' curves
  // draw as fast as one lap's.
  const picks = (n) => {
    const k = Math.max(1, Math.ceil(n / MAX_POINTS));
    const at = [];
    for (let i = 0; i < n; i += k) at.push(i);
    if (n > 0 && at[at.length - 1] !== n - 1) at.push(n - 1);
    return at;
  };
  // The curves hold one point per scan; each ends at the core's value
  // now, as the readouts do.
  const series = (at, value, get) => {
    const a = at.map(get);
    if (a.length) a[a.length - 1] = value;
    return a;
  };
  const c0 = w.weaver.entropyCurve(0);
  const c1 = w.weaver.entropyCurve(1);
  // A pane rebuilding has fewer points than the other: the x axis is the longer one's.
  const at = picks(Math.max(c0.length, c1.length));
  const upTo = (c, value) => series(at.filter((i) => i < c.length), value, (i) => c[i]);
  const e0 = upTo(c0, r.panes[0].entropyBits);
  const e1 = upTo(c1, r.panes[1].entropyBits);
  w.entropyChart.setData(at.map((i) => times[i]), e0, e1);
  w.entropyBox.dataset.last = JSON.stringify([e0[e0.length - 1] ?? null, e1[e1.length - 1] ?? null]);
  w.entropyBox.setAttribute('aria-label',
    `Map entropy over time, after ${fixed(r.time, 1)} s of driving: left map ${bits(r.panes[0].entropyBits)} bits, ` +
    `right map ${bits(r.panes[1].entropyBits)} bits.`);
  r.panes.forEach((pr, k) => {
    const flat = w.weaver.trackedHistory(k);
    const n = flat.length / 3;
    const mine = picks(n);
    const cells = [0, 1, 2].map((j) => series(mine, pr.tracked[j], (i) => flat[3 * i + j]));
    const p = w.panes[k];
    p.chartBox.dataset.last = JSON.stringify(cells.map((a) => a[a.length - 1] ?? null));
    p.chart.setData(mine.map((i) => times[i]), ...cells, new Array(mine.length).fill(pr.l0));
    p.chartBox.setAttribute('aria-label',
      `${p.side === 'left' ? 'Left' : 'Right'} map: log odds over time of three cells, now ` +
      w.tracked[k].map((c, i) => `${c.name} ${signed(pr.tracked[i], 2)}`).join(', ') + `; the prior l0 is ${fixed(pr.l0, 2)}.`);
  });
}

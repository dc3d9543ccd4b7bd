// <occgrid-map-weaver>'s charts: the two maps' entropy over time and each
// map's three tracked cells' log odds over time, drawn from the core's
// curves (one point per scan, at the scene's scan rate).
import { lineChart, COLORS } from './chart.js';
import { fixed } from './ui.js';
import { bits, signed } from './map-weaver-words.js';

/** The tracked cells: a wall cell, a corridor floor cell, a closet cell. */
export const TRACK_COLORS = [COLORS.series[2], COLORS.series[3], '#8c510a'];

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
  const times = Array.from(w.weaver.curveTimes());
  const t = (n) => times.slice(0, n);
  // The curves hold one point per scan, taken as the scan came in; a
  // slider moved since (while paused, say) has changed the maps, so
  // each curve ends at the core's value now, as the readouts do.
  const now = (curve, value) => {
    const a = Array.from(curve);
    if (a.length) a[a.length - 1] = value;
    return a;
  };
  const e0 = now(w.weaver.entropyCurve(0), r.panes[0].entropyBits);
  const e1 = now(w.weaver.entropyCurve(1), r.panes[1].entropyBits);
  w.entropyChart.setData(t(e0.length), e0, e1);
  w.entropyBox.dataset.last = JSON.stringify([e0[e0.length - 1] ?? null, e1[e1.length - 1] ?? null]);
  w.entropyBox.setAttribute('aria-label',
    `Map entropy over time, after ${fixed(r.time, 1)} s of driving: left map ${bits(r.panes[0].entropyBits)} bits, ` +
    `right map ${bits(r.panes[1].entropyBits)} bits.`);
  r.panes.forEach((pr, k) => {
    const flat = w.weaver.trackedHistory(k);
    const n = flat.length / 3;
    const series = [0, 1, 2].map((j) => now(Array.from({ length: n }, (_, i) => flat[3 * i + j]), pr.tracked[j]));
    const p = w.panes[k];
    p.chartBox.dataset.last = JSON.stringify(series.map((a) => a[a.length - 1] ?? null));
    p.chart.setData(t(n), ...series, new Array(n).fill(pr.l0));
    p.chartBox.setAttribute('aria-label',
      `${p.side === 'left' ? 'Left' : 'Right'} map: log odds over time of three cells, now ` +
      w.tracked[k].map((c, i) => `${c.name} ${signed(pr.tracked[i], 2)}`).join(', ') + `; the prior l0 is ${fixed(pr.l0, 2)}.`);
  });
}

// The Intel log in the browser: file input to finished map in Chromium
// (well under a second, 300 ms including reading the file), median of 5 fresh page loads, with the longest single call into the
// core (the page must stay responsive while it builds).
import fs from 'node:fs';
import path from 'node:path';
import { root } from '../lib/load-core.mjs';
import { median, round } from '../lib/stats.mjs';

export default async function (core, args) {
  const file = path.join(process.env.OCCGRID_DATASETS || path.join(root, '../shared/datasets'), 'intel-corrected.log.gz');
  const wanted = args.find((a) => !a.startsWith('-'));
  if (!fs.existsSync(file) || !fs.existsSync('/usr/bin/chromium') || (wanted && !'intel-browser'.includes(wanted))) return [];
  const { openPage, shutdown } = await import('../../tests/browser/harness.mjs');
  const totals = [];
  const longest = [];
  try {
    for (let k = 0; k < 5; k++) {
      const { page, close } = await openPage('/test-fixtures/real-log.html');
      await page.waitForSelector('#panel[data-ready]');
      await page.setInputFiles('.map-weaver-log input[type=file]', file);
      await page.waitForFunction(() => ['done', 'failed'].includes(document.querySelector('.map-weaver-log')?.dataset.state), null, { timeout: 60_000 });
      const state = await page.$eval('.map-weaver-log', (e) => ({ ...e.dataset }));
      if (state.state !== 'done') throw new Error(`the Intel log did not build: ${JSON.stringify(state)}`);
      totals.push(Number(state.totalMs));
      const trace = await page.evaluate(() => window.realLogPanel.trace);
      longest.push(Math.max(...trace.map(([, ms]) => ms)));
      await close();
    }
  } finally {
    await shutdown();
  }
  return [{
    workload: 'intel-browser', runtime: 'chromium', scans: 910, beams: 163800,
    total_ms: round(median(totals)), runs_ms: totals.map((t) => round(t, 1)), longest_call_ms: round(median(longest)),
  }];
}

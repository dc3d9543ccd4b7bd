// Map Weaver's time axis: with a scene of 6 scans per second, the entropy
// chart's last point and the "s of driving" readout give the same time,
// both from the core (a chart that assumed 12 scans per second put the 12th
// scan at 1 s while the readout said 2 s).
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

test('the chart time axis and the readout agree at a 6 Hz scan rate', async () => {
  const scene = encodeURIComponent(JSON.stringify({ scan_rate: 6 }));
  const { page, errors, close } = await openPage(
    `/?map-weaver.scene=${scene}&map-weaver.scans=12&map-weaver.autoplay=off#map-weaver`,
    { reducedMotion: 'reduce' },
  );
  const w = page.locator('occgrid-map-weaver');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-map-weaver')?.dataset.scans === '12', null, { timeout: 60_000 });
  const { chartLast, readout } = await w.evaluate((el) => ({
    chartLast: el.entropyChart.plot.data[0].at(-1),
    readout: el.weaver.readout().time,
  }));
  assert.equal(readout, 2, '12 scans at 6 per second are 2 s of driving');
  assert.equal(chartLast, readout, 'the chart ends where the readout is');
  const status = await w.locator('.map-weaver-status').textContent();
  assert.match(status, /2\.0 s of driving/);
  assert.deepEqual(errors, []);
  await close();
});

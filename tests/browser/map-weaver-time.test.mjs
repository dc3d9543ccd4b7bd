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

// Playback at speed 1 is real time at the scene's scan rate: half a second
// of frames integrates half a second of driving (a pacer fixed at 12 scans
// per second played a 6 Hz scene twice too fast). The frames are fed by
// hand, with their durations given, so nothing here depends on the clock.
test('playback at speed 1 keeps to the scene’s scan rate', async () => {
  const scene = encodeURIComponent(JSON.stringify({ scan_rate: 6 }));
  const { page, errors, close } = await openPage(
    `/?map-weaver.scene=${scene}&map-weaver.autoplay=off#map-weaver`,
    { reducedMotion: 'reduce' },
  );
  const w = page.locator('occgrid-map-weaver');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('occgrid-map-weaver')?.dataset.scans === '0', null, { timeout: 60_000 });
  const played = await w.evaluate((el) => {
    const run = (speed, frames) => {
      el.weaver.reset();
      el.options.speed = speed;
      el.play();
      // The frames below stand in for the browser's.
      el.loop.stop();
      for (const dt of frames) el.tick(dt);
      el.pause();
      const r = el.weaver.readout();
      return { scans: r.scans, time: r.time };
    };
    return { one: run(1, [250, 250]), two: run(2, [250, 250]) };
  });
  assert.deepEqual(played.one, { scans: 3, time: 0.5 }, 'speed 1: half a second of frames is half a second of driving');
  assert.deepEqual(played.two, { scans: 6, time: 1 }, 'speed 2: twice as much');
  assert.deepEqual(errors, []);
  await close();
});

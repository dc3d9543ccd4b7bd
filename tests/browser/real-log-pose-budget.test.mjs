// Map Weaver's real-log panel in Chromium, a log whose poses would cost
// past the pose budget to find (six thousand one-beam scans at SLAM):
// refused once read, and the status line says what helps (the core's
// advice: poses known in advance, or the scans that fit), not a coarser
// resolution, which does little for that work; poses known in advance then
// map it.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const PAGE = '/test-fixtures/real-log.html';
const SCANS = 6000;

/** `scans` FLASER lines of one beam 1.5 m ahead, creeping round a circle of 2 m. */
function oneBeamLog(scans) {
  const lines = [];
  for (let k = 0; k < scans; k++) {
    const a = k * 1e-3;
    const [x, y, th] = [2 * Math.cos(a), 2 * Math.sin(a), a + Math.PI / 2].map((v) => v.toFixed(4));
    lines.push(`FLASER 1 1.5 ${x} ${y} ${th} ${x} ${y} ${th} ${k} h ${k}`);
  }
  return `${lines.join('\n')}\n`;
}

/** Waits until the panel shows a state the session has stopped in, and returns the panel's data. */
async function stopped(page) {
  await page.waitForFunction(() => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    return !!s && s.state === panel.root.dataset.state && ['done', 'failed', 'awaiting-settings'].includes(s.state);
  }, null, { timeout: 120_000 });
  return page.$eval('.map-weaver-log', (e) => ({ ...e.dataset }));
}

test('a log whose SLAM poses pass the pose budget waits for settings, and the status says what fits', async () => {
  const { page, errors, close } = await openPage(PAGE);
  await page.waitForSelector('#panel[data-ready]');
  await page.selectOption('.map-weaver-log select[name=poses]', 'slam');
  await page.setInputFiles('.map-weaver-log input[type=file]', { name: 'one-beam.log', mimeType: 'text/plain', buffer: Buffer.from(oneBeamLog(SCANS)) });
  assert.equal((await stopped(page)).state, 'awaiting-settings');
  const error = await page.locator('.map-weaver-log .occgrid-error').textContent();
  assert.match(error, new RegExp(`invalid poses: "slam" over ${SCANS} scans .*could cost up to \\d+`));
  const fit = /or cut it to at most (\d+) scans\)$/.exec(error);
  assert.ok(fit && Number(fit[1]) < SCANS, error);
  const status = await page.locator('.map-weaver-log-status').textContent();
  assert.equal(status, `one-beam.log is read; its poses would cost too much to find: map it at the log's own poses or dead-reckoned ones, or cut it to at most ${fit[1]} scans.`);
  assert.doesNotMatch(status, /coarser/);
  // Poses known in advance map it.
  await page.selectOption('.map-weaver-log select[name=poses]', 'corrected');
  assert.equal((await stopped(page)).state, 'done');
  assert.equal(await page.evaluate(() => window.realLogPanel.session.state().scansDone), SCANS);
  assert.equal(errors.length, 1, errors.join('\n'));
  await close();
});

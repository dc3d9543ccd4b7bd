// The real-log panel's file input takes the same file twice: a browser
// reports a choice only when the input's value changes, so the panel
// empties the input once it has taken the file.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const LOG = Buffer.from([
  'FLASER 3 1.0 1.2 1.4 0 0 0 0 0 0 1 h 1',
  'FLASER 3 1.0 1.2 1.4 0.1 0 0 0.1 0 0 2 h 2',
  'FLASER 3 1.0 1.2 1.4 0.2 0 0 0.2 0 0 3 h 3',
  '',
].join('\n'));

async function settledOn(page, name) {
  await page.waitForFunction((n) => {
    const panel = window.realLogPanel ?? document.querySelector('occgrid-map-weaver')?.realLog;
    const s = panel?.session?.state();
    return !!s && s.state === 'done' && panel.root.dataset.state === 'done' && s.log === n;
  }, name, { timeout: 30_000 });
}

test('after a log is taken the file input is empty, so the same file chosen again is a new choice', async () => {
  const { page, errors, close } = await openPage('/test-fixtures/real-log.html');
  try {
    await page.waitForSelector('#panel[data-ready]');
    const input = '.map-weaver-log input[type=file]';
    await page.setInputFiles(input, { name: 'walk.log', mimeType: 'text/plain', buffer: LOG });
    await settledOn(page, 'walk.log');
    assert.equal(await page.$eval(input, (i) => i.value), '', 'the input keeps no file');
    assert.equal(await page.$eval(input, (i) => i.files.length), 0);
    await page.setInputFiles(input, { name: 'walk.log', mimeType: 'text/plain', buffer: LOG });
    await settledOn(page, 'walk.log');
    assert.deepEqual(errors, []);
  } finally {
    await close();
  }
});

// Map Weaver's real-log panel in Chromium: the cell model as a select, as
// the log-model attribute and in links, and a second map of the same log
// with another model beside the first.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const DATASETS = process.env.OCCGRID_DATASETS || path.resolve(import.meta.dirname, '../../../shared/datasets');
const PAGE = '/test-fixtures/real-log.html';

/** Waits until the session is done (or failed) and the panel shows it; returns the panel's data. */
async function settled(page, scans) {
  await page.waitForFunction((n) => {
    const panel = window.realLogPanel;
    const s = panel.session?.state();
    if (!s || s.state !== panel.root.dataset.state) return false;
    return (s.state === 'done' && s.scansDone === n) || s.state === 'failed';
  }, scans, { timeout: 60_000 });
  return page.$eval('.map-weaver-log', (e) => ({ ...e.dataset }));
}

test('the cell model select rebuilds the map, and a second model draws its map beside the first', async () => {
  const { page, errors, close } = await openPage(PAGE);
  await page.waitForSelector('#panel[data-ready]');
  const defaults = await page.evaluate(() => window.realLogPanel.core.RealLogSession.defaultSettings());
  assert.equal(defaults.model, 'hit-counting');
  assert.equal(await page.locator('.map-weaver-log select[name=model]').inputValue(), 'hit-counting');
  await page.setInputFiles('.map-weaver-log input[type=file]', path.join(DATASETS, 'intel-corrected.log.gz'));
  const counting = await settled(page, 910);
  assert.equal(counting.state, 'done');
  // Table 9.2's filter needs four beams to clear a cell: less of the floor is free.
  await page.selectOption('.map-weaver-log select[name=model]', 'log-odds');
  await page.waitForFunction(() => window.realLogPanel.session.state().settings.model === 'log-odds');
  const logOdds = await settled(page, 910);
  assert.ok(Number(logOdds.free) < Number(counting.free), `${logOdds.free} < ${counting.free}`);
  assert.equal(await page.locator('.map-weaver-log-reference').isHidden(), true, 'one map');

  await page.selectOption('.map-weaver-log select[name=compare-model]', 'hit-counting');
  await page.waitForFunction(() => window.realLogPanel.session.state().panes.length === 2);
  await settled(page, 910);
  const panes = await page.evaluate(() => window.realLogPanel.session.state().panes.map((p) => [p.poses, p.model, p.caption]));
  assert.deepEqual(panes.map(([poses, model]) => [poses, model]), [['corrected', 'log-odds'], ['corrected', 'hit-counting']]);
  assert.match(panes[1][2], /hit counting \(GMapping\)/);
  await page.locator('.map-weaver-log-reference').waitFor({ state: 'visible' });
  assert.match(await page.locator('.map-weaver-log-reference figcaption').textContent(), /hit counting/);
  const side = await page.evaluate(() => window.realLogPanel.session.counts(1));
  assert.equal(String(side.free), counting.free, 'the map beside is the counting map');

  // The same model twice is refused by name, and the maps stay.
  await page.selectOption('.map-weaver-log select[name=compare-model]', 'log-odds');
  await page.locator('.map-weaver-log > .occgrid-error').waitFor();
  assert.match(await page.locator('.map-weaver-log > .occgrid-error').textContent(), /compareModel/);
  assert.equal(await page.locator('.map-weaver-log select[name=compare-model]').inputValue(), 'hit-counting');
  // The panel says where each model comes from.
  assert.match(await page.locator('.map-weaver-log-models').textContent(), /GMapping.*Table 9\.2.*Cartographer/s);
  // The one refusal, and nothing else.
  assert.equal(errors.length, 1, errors.join(' | '));
  assert.match(errors[0], /invalid compareModel: "log-odds"/);
  await close();
});

test('log-model and log-compare-model are checked like the other attributes and set the panel up', async () => {
  const { page, errors, close } = await openPage('/');
  await page.evaluate(() => {
    const w = document.createElement('occgrid-map-weaver');
    w.id = 'models';
    w.setAttribute('mode', 'log');
    w.setAttribute('log-model', 'counting');
    w.setAttribute('log-compare-model', 'gmapping');
    w.setAttribute('autoplay', 'off');
    document.body.prepend(w);
  });
  const box = page.locator('#models > .occgrid-attribute-error');
  await box.waitFor();
  assert.match(await box.textContent(), /invalid log-model: "counting" \(expected one of "hit-counting", "log-odds", "hit-miss-odds"\)/);
  assert.match(await box.textContent(), /invalid log-compare-model: "gmapping"/);
  await page.evaluate(() => {
    const w = document.getElementById('models');
    w.setAttribute('log-model', 'hit-miss-odds');
    w.setAttribute('log-compare-model', 'log-odds');
  });
  await page.waitForFunction(() => !document.querySelector('#models > .occgrid-attribute-error'));
  await page.locator('#models .map-weaver-log').waitFor();
  await page.waitForFunction(() => document.querySelector('#models .map-weaver-log select[name=model]')?.value === 'hit-miss-odds');
  assert.equal(await page.locator('#models .map-weaver-log select[name=compare-model]').inputValue(), 'log-odds');
  const link = await page.evaluate(() => document.getElementById('models').linkState());
  assert.equal(link['log-model'], 'hit-miss-odds');
  assert.equal(link['log-compare-model'], 'log-odds');
  await page.evaluate(() => document.getElementById('models').setAttribute('log-compare-model', 'none'));
  await page.waitForFunction(() => document.querySelector('#models .map-weaver-log select[name=compare-model]')?.value === '');
  const none = await page.evaluate(() => document.getElementById('models').linkState());
  assert.equal(none['log-compare-model'], 'none');
  // The attribute's default is the core's.
  const core = await page.evaluate(async () => (await (await import('/widgets/lib/core.js')).loadLogCore()).core.RealLogSession.defaultSettings().model);
  const { LOG_MODEL_DEFAULT } = await page.evaluate(async () => ({ ...(await import('/widgets/lib/log-models.js')) }));
  assert.equal(LOG_MODEL_DEFAULT, core);
  assert.ok(errors.every((e) => /log-model|log-compare-model/.test(e)), errors.join(' | '));
  await close();
});

test('export-map takes --model and refuses a misspelt one by name', async () => {
  const { spawnSync } = await import('node:child_process');
  const fs = await import('node:fs');
  const os = await import('node:os');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'occgrid-models-'));
  // A wall 3 m ahead, seen twice from the origin.
  const ranges = Array.from({ length: 180 }, () => '3.0').join(' ');
  const log = path.join(dir, 'wall.log');
  fs.writeFileSync(log, [0, 1].map((k) => `FLASER 180 ${ranges} 0 0 0 0 0 0 ${k} host ${k}\n`).join(''));
  const script = path.resolve(import.meta.dirname, '../../scripts/export-map.mjs');
  const run = (...args) => spawnSync(process.execPath, [script, log, path.join(dir, 'map'), ...args], { encoding: 'utf8' });
  const byModel = {};
  for (const model of ['hit-counting', 'log-odds', 'hit-miss-odds']) {
    const r = run('--model', model);
    assert.equal(r.status, 0, r.stderr);
    byModel[model] = JSON.parse(r.stdout);
    assert.equal(byModel[model].model, model);
  }
  assert.equal(JSON.parse(run().stdout).model, 'hit-counting', 'the default');
  // Two beams clear a counting cell, not a Table 9.2 one (four needed).
  assert.ok(byModel['hit-counting'].free > byModel['log-odds'].free);
  const bad = run('--model', 'counting');
  assert.equal(bad.status, 1);
  assert.match(bad.stderr, /model/);
  assert.match(bad.stderr, /counting/);
  fs.rmSync(dir, { recursive: true });
});

// Embedding in Chromium: an instructor's bare page on another origin (a
// second server on another port, with a strict Content-Security-Policy of
// its own) loads each widget with one <script type="module"> from the
// project's server and its element; each widget finds its wasm and its
// stylesheets across origins and draws. Bad attribute values and unknown
// attribute names are reported inside the widget and in the console, and
// the widget still works. "Copy link" puts a widget's state in the page URL
// and the link restores it. Map Weaver's real-log mode is embedded the same
// way, with the log it loads named by an attribute (fetched only once the
// panel is on screen). The README documents every attribute.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { canvasColours, baseUrl, openPage, screenshot, serveForeign, shutdown } from './harness.mjs';

let project; // the project's server: http://127.0.0.1:PORT
let foreign; // the instructor's server, another origin

/** One bare page per case: a heading, the widget elements, their scripts. */
function page(title, body, modules) {
  return `<!doctype html>
<html lang="en">
<head>
  <meta charset="utf-8">
  <meta name="viewport" content="width=device-width, initial-scale=1">
  <title>${title}</title>
  <link rel="icon" href="data:,">
</head>
<body>
  <h1>${title}</h1>
  <p>An instructor's page that embeds a widget from another server.</p>
  ${body}
  ${modules.map((m) => `<script type="module" src="${project}/widgets/${m}.js"></script>`).join('\n  ')}
</body>
</html>
`;
}

/**
 * What each widget looks like once it has drawn, and how to read its
 * numbers. `tag` and `module` default to `occgrid-NAME` and `NAME`.
 */
const WIDGETS = {
  'cell-filter': {
    html: '<occgrid-cell-filter readings="ooff" prior="0.30"></occgrid-cell-filter>',
    ready: (w) => w.querySelectorAll('.cell-filter-table tbody tr').length === 5,
    numbers: (w) => [...w.querySelectorAll('.cell-filter-table tbody tr')].map((tr) => Number(tr.dataset.l)),
    canvases: '.cell-filter-chart canvas',
  },
  'map-weaver': {
    html: '<occgrid-map-weaver laps="1" scans="40" autoplay="off" speed="2"></occgrid-map-weaver>',
    ready: (w) => Number(w.dataset.scans) === 40,
    numbers: (w) => [...w.querySelectorAll('.map-weaver-pane')].map((p) => Number(p.dataset.entropy)),
    canvases: 'canvas.map-weaver-map',
  },
  'doorway-trap': {
    html: '<occgrid-doorway-trap scans="3" flips="2" autoplay="off"></occgrid-doorway-trap>',
    ready: (w) => w.dataset.scan === '3' && w.dataset.flips === '2' && w.querySelectorAll('.doorway-trap-joint tbody tr').length === 4,
    numbers: (w) => [Number(w.dataset.objective), ...[...w.querySelectorAll('.doorway-trap-joint td')].map((td) => Number(td.dataset.value))],
    canvases: 'canvas.doorway-trap-canvas, canvas.doorway-trap-diagram',
  },
  'sensor-fusion': {
    html: '<occgrid-sensor-fusion lidar-beams="12" scans="20" autoplay="off"></occgrid-sensor-fusion>',
    ready: (w) => w.dataset.step === '20' && w.dataset.lidarBeams === '12',
    numbers: (w) => [...w.querySelectorAll('.sensor-fusion-mean')].map((o) => Number(o.dataset.value)),
    canvases: 'canvas.sensor-fusion-map',
  },
  'inverse-workbench': {
    html: '<occgrid-inverse-workbench reading="3" seed="12" zoom="on" controls="reading zoom"></occgrid-inverse-workbench>',
    ready: (w) => w.dataset.state === 'ready' && w.dataset.reading === '3' && w.dataset.seed === '12'
      && /ranges 1\.5 to 4\.5 m/.test(w.querySelector('canvas.inverse-workbench-image').getAttribute('aria-label'))
      && w.querySelector('button[name=retrain]').hidden && w.querySelector('.occgrid-link').hidden,
    numbers: (w) => [...w.querySelectorAll('.inverse-workbench-free, .inverse-workbench-l0')].map((o) => Number.parseFloat(o.textContent)),
    canvases: 'canvas.inverse-workbench-image',
  },
  'map-weaver-log': {
    tag: 'occgrid-map-weaver',
    module: 'map-weaver',
    html: '<occgrid-map-weaver mode="log" log="intel-corrected.log.gz" log-resolution="0.1" controls="log-source log-settings export"></occgrid-map-weaver>',
    ready: (w) => {
      const d = w.querySelector('.map-weaver-log')?.dataset;
      return d?.state === 'done' && d.scans === '910' && w.realLog.geometry.resolution === 0.1
        && w.querySelector('.map-weaver-mode').hidden && !w.querySelector('.map-weaver-log-source').hidden;
    },
    numbers: (w) => {
      const d = w.querySelector('.map-weaver-log').dataset;
      return [d.scans, d.occupied, d.free, d.unknown].map(Number);
    },
    canvases: 'canvas.map-weaver-log-map',
  },
};
const tagOf = (name) => WIDGETS[name].tag ?? `occgrid-${name}`;

/** The CSP of the instructor's page: scripts, styles, wasm fetch only from the project's server. */
const foreignCsp = () => [
  "default-src 'none'",
  `script-src ${project} 'wasm-unsafe-eval'`,
  `style-src ${project}`,
  `connect-src ${project}`,
  'img-src data: blob:',
].join('; ');

before(async () => {
  project = await baseUrl();
  const pages = {};
  for (const [name, w] of Object.entries(WIDGETS)) pages[`/${name}.html`] = page(`Embedded ${name}`, w.html, [w.module ?? name]);
  pages['/bad.html'] = page('Bad attributes', [
    '<occgrid-cell-filter prior="1.5" p-occ="0.70"></occgrid-cell-filter>',
    '<occgrid-map-weaver laps="0" sede="3" autoplay="off"></occgrid-map-weaver>',
    '<occgrid-doorway-trap controls="playback, sliders, dance" autoplay="off"></occgrid-doorway-trap>',
    '<occgrid-sensor-fusion lidar-beams="lots" autoplay="off"></occgrid-sensor-fusion>',
  ].join('\n  '), ['cell-filter', 'map-weaver', 'doorway-trap', 'sensor-fusion']);
  pages['/bad-more.html'] = page('More bad attributes', [
    '<occgrid-inverse-workbench reading="9" zoom="maybe"></occgrid-inverse-workbench>',
    '<occgrid-map-weaver mode="log" log="../secret.log" log-resolution="0.07" autoplay="off"></occgrid-map-weaver>',
  ].join('\n  '), ['inverse-workbench', 'map-weaver']);
  // The log-mode widget far below the fold: it must not fetch its log until scrolled to.
  pages['/below.html'] = page('A log below the fold', [
    ...Array.from({ length: 60 }, (_, i) => `<p>Paragraph ${i + 1} of the instructor’s notes.</p>`),
    '<occgrid-map-weaver mode="log" log="aces-corrected.log.gz" autoplay="off"></occgrid-map-weaver>',
  ].join('\n  '), ['map-weaver']);
  pages['/two.html'] = page('Two widgets and a link', [
    '<occgrid-sensor-fusion id="fusion" autoplay="off"></occgrid-sensor-fusion>',
    '<occgrid-cell-filter controls="readings link"></occgrid-cell-filter>',
  ].join('\n  '), ['sensor-fusion', 'cell-filter']);
  foreign = await serveForeign(pages, { headers: { 'Content-Security-Policy': foreignCsp() } });
});

after(async () => {
  await foreign?.close();
  await shutdown();
});

for (const [name, spec] of Object.entries(WIDGETS)) {
  test(`${name} embedded alone in a page on another origin under a strict CSP finds its wasm and styles and draws`, async () => {
    const { page: p, errors, close } = await openPage(`${foreign.origin}/${name}.html`, { viewport: { width: 1000, height: 900 } });
    assert.notEqual(new URL(p.url()).origin, project, 'the page is on another origin');
    const tag = tagOf(name);
    const w = p.locator(tag);
    await w.scrollIntoViewIfNeeded();
    // Polled from here: the page's CSP rightly forbids evaluating code strings.
    let ready = false;
    for (const until = Date.now() + 60_000; !ready && Date.now() < until;) {
      ready = await w.evaluate(spec.ready);
      if (!ready) await p.waitForTimeout(100);
    }
    assert.ok(ready, `${tag} became ready`);
    // Every canvas holds a picture, every number is a number.
    const c = await canvasColours(w, spec.canvases);
    assert.ok(c.length >= 1, 'the widget has canvases');
    assert.ok(c.every((n) => n > 2), `non-blank canvases: ${c}`);
    const numbers = await w.evaluate(spec.numbers);
    assert.ok(numbers.length >= 2 && numbers.every(Number.isFinite), `numbers shown: ${numbers}`);
    // The stylesheets came from the project's server and apply here.
    const look = await w.evaluate((el) => ({
      display: getComputedStyle(el).display,
      border: getComputedStyle(el).borderTopStyle,
      sheets: [...document.styleSheets].map((s) => s.href || ''),
    }));
    assert.equal(look.display, 'block');
    assert.equal(look.border, 'solid');
    assert.ok(look.sheets.some((h) => h.startsWith(project) && h.endsWith('/widgets/lib/occgrid.css')), look.sheets.join(', '));
    if (await w.locator('.uplot').count()) {
      assert.ok(look.sheets.some((h) => h.startsWith(project) && h.endsWith('uPlot.min.css')), 'uPlot’s stylesheet too');
    }
    await screenshot(w, `embedded-${name}`);
    assert.deepEqual(errors, [], 'no console errors, no CSP violations');
    await close();
  });
}

test('bad attribute values and unknown attribute names are reported inside each widget and in the console; the widgets still draw', async () => {
  const { page: p, errors, logs, close } = await openPage(`${foreign.origin}/bad.html`, { viewport: { width: 1000, height: 900 } });
  const warnings = () => logs.filter((m) => m.type === 'warning').map((m) => m.text);
  const report = (tag) => p.locator(`${tag} > .occgrid-attribute-error`);
  const cases = [
    ['occgrid-cell-filter', /invalid prior: "1\.5" \(expected a probability strictly between 0 and 1/],
    ['occgrid-map-weaver', /invalid laps: "0" \(expected a whole number from 1 to 20\)/],
    ['occgrid-doorway-trap', /invalid controls: "playback, sliders, dance" \(unknown group "dance"; expected "all", "none" or any of: playback, arrangements, sliders, export, link\)/],
    ['occgrid-sensor-fusion', /invalid lidar-beams: "lots" \(expected a whole number from 1 to 2048\)/],
  ];
  for (const [tag, message] of cases) {
    await report(tag).waitFor();
    assert.match(await report(tag).textContent(), message, tag);
    assert.equal(await report(tag).getAttribute('role'), 'alert');
    assert.ok(errors.some((e) => e.startsWith(`${tag}: `) && message.test(e)), `${tag} logs the message: ${errors.join(' | ')}`);
  }
  // The unknown name is a notice of its own, with the names the widget knows.
  const notice = p.locator('occgrid-map-weaver > .occgrid-attribute-warning');
  await notice.waitFor();
  assert.match(await notice.textContent(), /unknown attribute sede="3" \(ignored; occgrid-map-weaver knows: seed, laps, scene, person, speed, autoplay, scans, mode/);
  assert.ok(warnings().some((m) => /occgrid-map-weaver: unknown attribute sede="3"/.test(m)), warnings().join(' | '));
  // Only the four bad values were logged as errors.
  assert.equal(errors.length, 4, errors.join(' | '));

  // Each widget works with its defaults in place of the bad value.
  await p.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 4);
  assert.equal(await p.locator('occgrid-cell-filter').getByLabel('prior p(m)').inputValue(), '0.5');
  assert.equal(await p.locator('occgrid-cell-filter').getByLabel('p(m | occupied reading)').inputValue(), '0.7');
  const weaver = p.locator('occgrid-map-weaver');
  await weaver.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-map-weaver').dataset.scans === '0', null, { timeout: 30_000 });
  assert.match(await weaver.locator('.map-weaver-status').textContent(), /Lap 1 of 3/);
  await weaver.getByRole('button', { name: 'Step' }).click();
  assert.equal(await weaver.getAttribute('data-scans'), '1');
  const fusion = p.locator('occgrid-sensor-fusion');
  await fusion.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-sensor-fusion').dataset.lidarBeams === '360');
  // A bad `controls` keeps every control.
  const trap = p.locator('occgrid-doorway-trap');
  assert.equal(await trap.getByRole('button', { name: 'Export map (MAP map)' }).isVisible(), true);
  await screenshot(p.locator('body'), 'embedded-bad-attributes');

  // Correcting an attribute clears its report; an unknown name going away clears the notice.
  await p.evaluate(() => {
    document.querySelector('occgrid-map-weaver').setAttribute('laps', '2');
    document.querySelector('occgrid-map-weaver').removeAttribute('sede');
    document.querySelector('occgrid-cell-filter').setAttribute('prior', '0.25');
  });
  await p.waitForFunction(() => !document.querySelector('occgrid-map-weaver > .occgrid-attribute-error'));
  await p.waitForFunction(() => /Lap 1 of 2/.test(document.querySelector('occgrid-map-weaver .map-weaver-status').textContent), null, { timeout: 30_000 });
  assert.equal(await p.locator('occgrid-map-weaver > .occgrid-attribute-warning').count(), 0);
  assert.equal(await report('occgrid-cell-filter').count(), 0);
  assert.equal(await p.locator('occgrid-cell-filter').getByLabel('prior p(m)').inputValue(), '0.25');
  await close();
});

test('bad values of the workbench’s and the real-log mode’s attributes are reported in the widget; correcting them applies them', async () => {
  const { page: p, errors, close } = await openPage(`${foreign.origin}/bad-more.html`, { viewport: { width: 1000, height: 900 } });
  const requested = [];
  p.on('request', (r) => requested.push(r.url()));
  const bench = p.locator('occgrid-inverse-workbench');
  const weaver = p.locator('occgrid-map-weaver');
  const messages = {
    reading: /invalid reading: "9" \(expected a number from 0\.2 to 8 m in steps of 0\.05\)/,
    zoom: /invalid zoom: "maybe" \(expected "on" or "off"\)/,
    log: /invalid log: "\.\.\/secret\.log" \(expected the file name of a CARMEN log or a ROS 2 bag in the server’s \/datasets\/, such as "intel-corrected\.log\.gz" or "intel-perfect\.mcap"\)/,
    resolution: /invalid log-resolution: "0\.07" \(expected one of "0\.025", "0\.05", "0\.1", "0\.2"\)/,
  };
  const benchBox = bench.locator(':scope > .occgrid-attribute-error');
  const weaverBox = weaver.locator(':scope > .occgrid-attribute-error');
  await benchBox.waitFor();
  await weaverBox.waitFor();
  assert.equal(await benchBox.getAttribute('role'), 'alert');
  assert.match(await benchBox.textContent(), messages.reading);
  assert.match(await benchBox.textContent(), messages.zoom);
  assert.match(await weaverBox.textContent(), messages.log);
  assert.match(await weaverBox.textContent(), messages.resolution);
  for (const [key, m] of Object.entries(messages)) {
    const tag = key === 'reading' || key === 'zoom' ? 'occgrid-inverse-workbench' : 'occgrid-map-weaver';
    assert.ok(errors.some((e) => e.startsWith(`${tag}: `) && m.test(e)), `${key} is logged: ${errors.join(' | ')}`);
  }
  assert.equal(errors.length, 4, errors.join(' | '));

  // The workbench draws with the defaults in place of the bad values.
  await bench.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.state === 'ready', null, { timeout: 30_000 });
  assert.equal(await bench.getAttribute('data-reading'), '2');
  assert.equal(await bench.getByLabel(/^Zoom to/).isChecked(), false);
  // The real-log panel opens with its default resolution and loads nothing.
  await weaver.scrollIntoViewIfNeeded();
  await weaver.locator('.map-weaver-log').waitFor();
  await p.waitForTimeout(500);
  assert.equal(await weaver.locator('.map-weaver-log select[name=resolution]').inputValue(), '0.05');
  assert.equal(await weaver.locator('.map-weaver-log').getAttribute('data-state'), 'idle');
  assert.deepEqual(requested.filter((u) => /secret|\.log(\.gz)?$/.test(u)), [], 'no log was fetched');
  await screenshot(p.locator('body'), 'embedded-bad-attributes-more');

  // Good values: the workbench follows; the panel takes the resolution, then loads the named log.
  await bench.evaluate((el) => {
    el.setAttribute('reading', '3.5');
    el.setAttribute('zoom', 'on');
  });
  await p.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.reading === '3.5');
  assert.equal(await bench.locator(':scope > .occgrid-attribute-error').count(), 0);
  assert.equal(await bench.getByLabel(/^Zoom to/).isChecked(), true);
  assert.equal(await bench.getByLabel('Reading z').inputValue(), '3.5');
  await weaver.evaluate((el) => el.setAttribute('log-resolution', '0.1'));
  assert.equal(await weaver.locator('.map-weaver-log select[name=resolution]').inputValue(), '0.1');
  assert.match(await weaverBox.textContent(), messages.log, 'the bad log is still reported');
  assert.doesNotMatch(await weaverBox.textContent(), /log-resolution/);
  await weaver.evaluate((el) => el.setAttribute('log', 'aces-corrected.log.gz'));
  // The panel may still read "done" from the resolution change for a moment
  // after the log is named: wait for the log's own finished status, polled
  // from here (the page's CSP forbids evaluating code strings).
  let finished = false;
  for (const until = Date.now() + 30_000; !finished && Date.now() < until;) {
    finished = await weaver.evaluate((w) => /440 of 440 scans/.test(w.querySelector('.map-weaver-log-status')?.textContent ?? '')
      && w.querySelector('.map-weaver-log')?.dataset.state === 'done');
    if (!finished) await p.waitForTimeout(100);
  }
  assert.match(await weaver.locator('.map-weaver-log-status').textContent(), /440 of 440 scans, .* at 0\.1 m/);
  assert.equal(await weaverBox.count(), 0);
  assert.equal(await weaver.locator('.map-weaver-log select[name=dataset]').inputValue(), 'aces-corrected.log.gz', 'the menu shows the log');
  assert.equal(errors.length, 4, errors.join(' | '));
  await close();
});

test('a real-log widget below the fold fetches its log only when scrolled into view', async () => {
  const { page: p, errors, close } = await openPage(`${foreign.origin}/below.html`, { viewport: { width: 1000, height: 700 } });
  const fetched = [];
  p.on('request', (r) => { if (r.url().endsWith('/datasets/aces-corrected.log.gz')) fetched.push(r.url()); });
  const weaver = p.locator('occgrid-map-weaver');
  await weaver.locator('.map-weaver-log').waitFor({ state: 'attached', timeout: 30_000 });
  await p.waitForTimeout(1000);
  assert.equal(await weaver.evaluate((w) => w.getBoundingClientRect().top > window.innerHeight), true, 'out of view');
  assert.deepEqual(fetched, [], 'nothing fetched while out of view');
  assert.equal(await weaver.locator('.map-weaver-log').getAttribute('data-state'), 'idle');
  await weaver.locator('.map-weaver-log').scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('.map-weaver-log')?.dataset.state === 'done', null, { timeout: 30_000 });
  assert.equal(fetched.length, 1);
  assert.match(await weaver.locator('.map-weaver-log-status').textContent(), /440 of 440 scans/);
  assert.deepEqual(errors, []);
  await close();
});

test('the controls attribute shows only the groups it names', async () => {
  const { page: p, errors, close } = await openPage(`${foreign.origin}/two.html`, { viewport: { width: 1000, height: 900 } });
  const filter = p.locator('occgrid-cell-filter');
  await filter.locator('.cell-filter-table tbody tr').first().waitFor();
  assert.equal(await filter.getByRole('button', { name: 'Occupied reading' }).isVisible(), true);
  assert.equal(await filter.getByRole('button', { name: 'Copy link' }).isVisible(), true);
  for (const hidden of ['Worked example', 'The l0 lesson']) {
    assert.equal(await filter.getByRole('button', { name: hidden }).isVisible(), false, hidden);
  }
  assert.equal(await filter.getByLabel('prior p(m)').isVisible(), false);
  assert.equal(await filter.getByLabel('forget to subtract l0').isVisible(), false);
  // Changing the attribute brings them back.
  await filter.evaluate((el) => el.setAttribute('controls', 'all'));
  assert.equal(await filter.getByLabel('prior p(m)').isVisible(), true);
  assert.equal(await filter.getByRole('button', { name: 'The l0 lesson' }).isVisible(), true);
  assert.deepEqual(errors, []);
  await close();
});

test('Copy link puts each widget’s state in the page URL, and opening the link restores it', async () => {
  const { page: p, errors, close } = await openPage(`${foreign.origin}/two.html`, { viewport: { width: 1000, height: 900 } });
  await p.context().grantPermissions(['clipboard-read', 'clipboard-write'], { origin: foreign.origin });
  const fusion = p.locator('occgrid-sensor-fusion');
  const filter = p.locator('occgrid-cell-filter');
  await p.waitForFunction(() => document.querySelector('occgrid-sensor-fusion').dataset.step === '0');
  await filter.locator('.cell-filter-table tbody tr').first().waitFor();
  // The reader changes both widgets: fewer beams and 7 scans; other readings.
  const beams = fusion.getByLabel('LiDAR beams');
  await beams.focus();
  for (let i = 0; i < 4; i++) await p.keyboard.press('ArrowLeft');
  await p.waitForFunction(() => document.querySelector('occgrid-sensor-fusion').dataset.lidarBeams === '60');
  for (let i = 0; i < 7; i++) await fusion.getByRole('button', { name: 'Step' }).click();
  await filter.getByRole('button', { name: 'Clear readings' }).click();
  await filter.getByRole('button', { name: 'Free reading' }).click();
  await filter.getByRole('button', { name: 'Occupied reading' }).click();
  await filter.evaluate((el) => el.setAttribute('prior', '0.35'));
  await fusion.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /fusion\./.test(location.search));
  await filter.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /cell-filter\./.test(location.search));
  const link = p.url();
  const url = new URL(link);
  assert.equal(url.origin, foreign.origin);
  assert.equal(url.searchParams.get('fusion.lidar-beams'), '60', link);
  assert.equal(url.searchParams.get('fusion.scans'), '7', link);
  assert.equal(url.searchParams.get('fusion.autoplay'), 'off', link);
  assert.equal(url.searchParams.get('cell-filter.readings'), 'fo', link);
  assert.equal(url.searchParams.get('cell-filter.prior'), '0.35', link);
  assert.equal(url.searchParams.get('cell-filter.controls'), 'readings link', link);
  assert.equal(url.searchParams.has('cell-filter.p-occ'), false, 'defaults stay out of the link');
  assert.equal(url.hash, '#fusion', 'the fragment points at the widget with an id (the other has none to point at)');
  assert.equal(await p.evaluate(() => navigator.clipboard.readText()), link, 'the link is on the clipboard');
  assert.match(await filter.locator('.occgrid-link-status').textContent(), /Link copied/);

  // A reader opens the link: both widgets come back as they were.
  const other = await openPage(link, { viewport: { width: 1000, height: 900 } });
  const f2 = other.page.locator('occgrid-sensor-fusion');
  await other.page.waitForFunction(() => document.querySelector('occgrid-sensor-fusion').dataset.step === '7', null, { timeout: 30_000 });
  assert.equal(await f2.getAttribute('data-lidar-beams'), '60');
  assert.match(await f2.locator('.sensor-fusion-lidar figcaption').textContent(), /60 beams/);
  await other.page.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 3);
  const rows = await other.page.$$eval('occgrid-cell-filter .cell-filter-table tbody tr', (trs) => trs.map((tr) => tr.children[1].textContent));
  assert.deepEqual(rows, ['prior', 'free', 'occupied']);
  assert.equal(await other.page.locator('occgrid-cell-filter').getByLabel('prior p(m)').inputValue(), '0.35');
  assert.equal(await other.page.locator('occgrid-cell-filter').getByRole('button', { name: 'Worked example' }).isVisible(), false);
  assert.deepEqual(other.errors, []);
  await other.close();
  assert.deepEqual(errors, []);
  await close();
});

test('the chapter page’s links restore Map Weaver and the doorway trap mid-run', async () => {
  const { page: p, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  const weaver = p.locator('occgrid-map-weaver');
  await weaver.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-map-weaver').dataset.scans === '0', null, { timeout: 30_000 });
  for (let i = 0; i < 5; i++) await weaver.getByRole('button', { name: 'Step' }).click();
  await weaver.locator('.map-weaver-right').getByLabel('Pose oracle').uncheck();
  await weaver.locator('.map-weaver-left').getByLabel('Clamp l_max').fill('4');
  await weaver.getByLabel('Speed').selectOption('4');
  await weaver.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /map-weaver\./.test(location.search));
  const trap = p.locator('occgrid-doorway-trap');
  await trap.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '0');
  await trap.getByRole('button', { name: 'Next scan' }).click();
  await trap.getByRole('button', { name: 'Next scan' }).click();
  await trap.getByRole('button', { name: 'Step the MAP climb by one flip' }).click();
  await trap.getByRole('button', { name: 'Collinear' }).click();
  await trap.getByLabel('Reading z').fill('2.5');
  await trap.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /doorway-trap\./.test(location.search));
  const link = new URL(p.url());
  assert.equal(link.pathname, '/');
  assert.equal(link.hash, '#doorway-trap', 'opens at the widget’s section');
  const expected = {
    'map-weaver.scans': '5', 'map-weaver.right-pose': 'dead-reckoning', 'map-weaver.left-clamp': '4', 'map-weaver.speed': '4',
    'map-weaver.autoplay': 'off', 'doorway-trap.scans': '2', 'doorway-trap.flips': '1', 'doorway-trap.arrangement': 'collinear',
    'doorway-trap.reading': '2.50',
  };
  for (const [k, v] of Object.entries(expected)) assert.equal(link.searchParams.get(k), v, `${k} in ${link}`);

  const other = await openPage(link.href, { reducedMotion: 'no-preference' });
  const o = other.page;
  const w2 = o.locator('occgrid-map-weaver');
  await w2.scrollIntoViewIfNeeded();
  await o.waitForFunction(() => document.querySelector('occgrid-map-weaver').dataset.scans === '5', null, { timeout: 30_000 });
  assert.equal(await w2.locator('.map-weaver-right').getAttribute('data-pose'), 'dead-reckoning');
  assert.equal(await w2.locator('.map-weaver-left').getByLabel('Clamp l_max').inputValue(), '4');
  assert.equal(await w2.getByLabel('Speed').inputValue(), '4');
  await o.waitForTimeout(400);
  assert.equal(await w2.getAttribute('data-scans'), '5', 'autoplay=off: the restored run waits');
  const t2 = o.locator('occgrid-doorway-trap');
  await t2.scrollIntoViewIfNeeded();
  await o.waitForFunction(() => document.querySelector('occgrid-doorway-trap').dataset.flips === '1');
  assert.equal(await t2.getAttribute('data-scan'), '2');
  assert.equal(await t2.getByRole('button', { name: 'Collinear' }).getAttribute('aria-pressed'), 'true');
  assert.equal(await t2.getByLabel('Reading z').inputValue(), '2.5');
  assert.deepEqual(other.errors, []);
  await other.close();
  assert.deepEqual(errors, []);
  await close();
});

test('links restore the inverse workbench and Map Weaver’s real-log mode', async () => {
  const { page: p, errors, close } = await openPage('/', { reducedMotion: 'reduce' });
  await p.context().grantPermissions(['clipboard-read', 'clipboard-write'], { origin: new URL(p.url()).origin });
  const bench = p.locator('occgrid-inverse-workbench');
  await bench.scrollIntoViewIfNeeded();
  await p.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.state === 'ready', null, { timeout: 30_000 });
  await bench.getByLabel('Reading z').fill('4.5');
  await bench.getByLabel(/^Zoom to/).check();
  await bench.getByLabel('Seed').fill('12');
  await bench.getByRole('button', { name: 'Retrain' }).click();
  await p.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.seed === '12', null, { timeout: 30_000 });
  await bench.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /inverse-workbench\./.test(location.search));

  const weaver = p.locator('occgrid-map-weaver');
  await weaver.scrollIntoViewIfNeeded();
  await weaver.getByLabel('Real log').check();
  await weaver.locator('.map-weaver-log select[name=dataset] option[value="aces-corrected.log.gz"]').waitFor({ state: 'attached' });
  await weaver.locator('.map-weaver-log select[name=dataset]').selectOption('aces-corrected.log.gz');
  await p.waitForFunction(() => document.querySelector('.map-weaver-log').dataset.state === 'done', null, { timeout: 30_000 });
  await weaver.locator('.map-weaver-log select[name=resolution]').selectOption('0.1');
  await p.waitForFunction(() => document.querySelector('occgrid-map-weaver').realLog.geometry?.resolution === 0.1
    && document.querySelector('.map-weaver-log').dataset.state === 'done', null, { timeout: 30_000 });
  await weaver.locator('.map-weaver-log input[name=l-free]').fill('-0.6');
  await p.waitForFunction(() => document.querySelector('occgrid-map-weaver').realLog.applied.lFree === -0.6);
  await weaver.getByRole('button', { name: 'Copy link' }).click();
  await p.waitForFunction(() => /map-weaver\.mode=log/.test(location.search));
  const link = new URL(p.url());
  const expected = {
    'inverse-workbench.reading': '4.50', 'inverse-workbench.zoom': 'on', 'inverse-workbench.seed': '12',
    'map-weaver.mode': 'log', 'map-weaver.log': 'aces-corrected.log.gz', 'map-weaver.log-resolution': '0.1',
    'map-weaver.log-l-free': '-0.60',
  };
  for (const [k, v] of Object.entries(expected)) assert.equal(link.searchParams.get(k), v, `${k} in ${link}`);
  for (const k of ['inverse-workbench.controls', 'map-weaver.log-range-cap', 'map-weaver.log-alpha', 'map-weaver.log-l-occ', 'map-weaver.log-clamp']) {
    assert.equal(link.searchParams.has(k), false, `${k} is at its default and stays out of ${link}`);
  }
  assert.equal(link.hash, '#map-weaver');

  const other = await openPage(link.href, { reducedMotion: 'reduce' });
  const o = other.page;
  const w2 = o.locator('occgrid-map-weaver');
  await w2.scrollIntoViewIfNeeded();
  await o.waitForFunction(() => document.querySelector('.map-weaver-log')?.dataset.state === 'done', null, { timeout: 30_000 });
  assert.equal(await w2.getByLabel('Real log').isChecked(), true);
  assert.match(await w2.locator('.map-weaver-log-status').textContent(), /440 of 440 scans, .* at 0\.1 m/);
  assert.equal(await w2.locator('.map-weaver-log input[name=l-free]').inputValue(), '-0.6');
  assert.equal(await o.evaluate(() => document.querySelector('occgrid-map-weaver').realLog.applied.lFree), -0.6);
  const b2 = o.locator('occgrid-inverse-workbench');
  await b2.scrollIntoViewIfNeeded();
  await o.waitForFunction(() => document.querySelector('occgrid-inverse-workbench').dataset.state === 'ready', null, { timeout: 30_000 });
  assert.equal(await b2.getAttribute('data-reading'), '4.5');
  assert.equal(await b2.getAttribute('data-seed'), '12');
  assert.equal(await b2.getByLabel(/^Zoom to/).isChecked(), true);
  assert.deepEqual(other.errors, []);
  await other.close();
  assert.deepEqual(errors, []);
  await close();
});

test('the README’s Embedding section shows every widget with every attribute it knows', async () => {
  const readme = fs.readFileSync(path.resolve(import.meta.dirname, '../../README.md'), 'utf8');
  const start = readme.indexOf('## Embedding');
  assert.ok(start >= 0, 'README has an "## Embedding" section');
  const section = readme.slice(start, readme.indexOf('\n## ', start + 5));
  const { page: p, close } = await openPage('/');
  const tags = ['occgrid-cell-filter', 'occgrid-map-weaver', 'occgrid-doorway-trap', 'occgrid-sensor-fusion', 'occgrid-inverse-workbench'];
  await p.waitForFunction((t) => t.every((tag) => customElements.get(tag)), tags);
  const specs = await p.evaluate((t) => Object.fromEntries(t.map((tag) => [tag, Object.keys(customElements.get(tag).attributeSpec)])), tags);
  for (const [tag, names] of Object.entries(specs)) {
    // The example with the most attributes is the widget's full one.
    const examples = [...section.matchAll(new RegExp(`<${tag}\\s[\\s\\S]*?</${tag}>`, 'g'))].map((m) => m[0]);
    const example = examples.reduce((a, b) => (b.split('=').length > a.split('=').length ? b : a), '');
    assert.ok(example.length > 0, `an example of <${tag}>`);
    for (const n of names) {
      assert.match(example, new RegExp(`\\s${n}=`), `<${tag}> example shows ${n}`);
      assert.match(section, new RegExp(`\`${n}\``), `${n} is described`);
    }
  }
  await close();

  // Pasted into a page as they are, the examples load without a single complaint.
  const html = [...section.matchAll(/```html\n([\s\S]*?)```/g)].map((m) => m[1])
    .filter((block) => tags.some((t) => block.includes(`<${t} `)))
    // `https://HOST/PATH/` is where an instructor put the bundle; here the
    // project's server plays that host.
    .join('\n').replaceAll('https://HOST/PATH', project).replaceAll('https://HOST', project);
  const pasted = await serveForeign({ '/readme.html': `<!doctype html><html lang="en"><head><meta charset="utf-8"><title>README examples</title><link rel="icon" href="data:,"></head><body>${html}</body></html>` });
  const { page: q, errors, logs, close: closeQ } = await openPage(`${pasted.origin}/readme.html`, { reducedMotion: 'reduce' });
  for (const tag of tags) {
    for (const w of await q.locator(tag).all()) {
      // Scrolled to as a reader scrolls, without waiting for the page to stop
      // moving: the widgets above start one after another and grow as they do.
      await w.evaluate((e) => e.scrollIntoView({ block: 'center' }));
      await q.waitForTimeout(100);
    }
    await q.waitForFunction((t) => [...document.querySelectorAll(t)].every((e) => e.querySelector('canvas')), tag);
  }
  await q.waitForFunction(() => document.querySelector('occgrid-map-weaver[left-model]')?.dataset.scans === '0', null, { timeout: 30_000 });
  await q.waitForFunction(() => document.querySelector('occgrid-doorway-trap')?.dataset.flips === '0');
  await q.waitForFunction(() => document.querySelector('occgrid-inverse-workbench')?.dataset.state === 'ready', null, { timeout: 30_000 });
  // The real-log example loads its log once seen, at its resolution.
  await q.waitForFunction(() => document.querySelector('occgrid-map-weaver[mode=log] .map-weaver-log')?.dataset.state === 'done', null, { timeout: 30_000 });
  assert.match(await q.locator('occgrid-map-weaver[mode=log] .map-weaver-log-status').textContent(), /440 of 440 scans, .* at 0\.1 m/);
  assert.equal(await q.locator('.occgrid-attribute-error, .occgrid-attribute-warning, .occgrid-error').count(), 0);
  assert.deepEqual(errors, []);
  assert.deepEqual(logs.filter((m) => m.type === 'warning'), []);
  // cells="2.0,-3,2.0,3" are where "side by side" puts them.
  assert.equal(await q.locator('occgrid-doorway-trap').getByRole('button', { name: 'Side by side' }).getAttribute('aria-pressed'), 'true');
  await closeQ();
  await pasted.close();
});

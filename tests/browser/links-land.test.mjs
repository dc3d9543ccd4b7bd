// Links in Chromium: every exercise link of the chapter, opened at
// 1280 x 800, lands with its widget on screen (the doorway trap's two-cell
// links on the two-cell table), and the widget starts and draws; and a
// link's keys replace only the attributes they name, so a course page's own
// attributes survive, and a copied link on that page names a default the
// reader went back to where the page gave another value. Exercise 1's ten
// readings fit the cell filter's table without its inner scroll.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { baseUrl, openPage, serveForeign, shutdown } from './harness.mjs';

const LAPTOP = { width: 1280, height: 800 };
let course;

before(async () => {
  const project = await baseUrl();
  course = await serveForeign({
    '/weaver.html': `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>Course</title><link rel="icon" href="data:,"></head>
<body><h1>Ghosts</h1>
<occgrid-map-weaver id="mwB" left-clamp="4" autoplay="off" scans="100"></occgrid-map-weaver>
<script type="module" src="${project}/widgets/map-weaver.js"></script>
</body></html>
`,
  });
});

after(async () => {
  await course?.close();
  await shutdown();
});

/** True once widget `w` (tag `t`) has started and drawn (runs in the page). */
const drawn = (t) => {
  const w = document.querySelector(t);
  if (!w) return false;
  if (t === 'occgrid-cell-filter') return w.dataset.l !== undefined;
  // A run made and its maps drawn (under reduced motion it does not play).
  if (t === 'occgrid-map-weaver') return !!w.weaver && w.dataset.scans !== undefined && w.querySelector('canvas.map-weaver-map').width > 1;
  if (t === 'occgrid-doorway-trap') return w.dataset.flips !== undefined && w.querySelectorAll('.doorway-trap-joint tbody tr').length === 4;
  return w.dataset.step !== undefined;
};

test('every exercise link at 1280 x 800 lands with its widget on screen, and the widget starts and draws', async () => {
  const { page, close } = await openPage('/', { viewport: LAPTOP });
  const links = await page.evaluate(() => [...document.querySelectorAll('a[data-exercise]')].map((a) => ({ n: a.dataset.exercise, href: a.getAttribute('href') })));
  await close();
  assert.equal(links.length, 8);
  for (const { n, href } of links) {
    const { page: p, errors, close: done } = await openPage(`/${href}`, { viewport: LAPTOP, reducedMotion: 'reduce' });
    const tag = `occgrid-${href.split('#')[1]}`;
    await p.waitForFunction(drawn, tag, { timeout: 120_000 });
    // Once the page has settled (the widget's start done), the widget, or
    // the part the link is about, is inside the window.
    const seen = await p.evaluate((t) => {
      const w = document.querySelector(t);
      const part = t === 'occgrid-doorway-trap' && /arrangement|reading/.test(location.search) ? w.querySelector('.doorway-trap-two-cell') : w;
      const r = part.getBoundingClientRect();
      return { top: r.top, bottom: r.bottom, part: part.className || part.localName };
    }, tag);
    assert.ok(seen.top < LAPTOP.height - 200 && seen.bottom > 200,
      `exercise ${n}: ${seen.part} spans y ${seen.top.toFixed(0)}–${seen.bottom.toFixed(0)} of an 800 px window`);
    assert.ok(seen.top > -LAPTOP.height / 2, `exercise ${n}: landed ${(-seen.top).toFixed(0)} px into the widget`);
    assert.deepEqual(errors, [], `exercise ${n}`);
    await done();
  }
});

test('a link replaces only the attributes it names: a course page’s own attributes survive, and a copied link overrides them where the reader changed them', async () => {
  const { page, errors, close } = await openPage(`${course.origin}/weaver.html?mwB.left-strength=2`, { viewport: LAPTOP, reducedMotion: 'reduce' });
  const w = page.locator('#mwB');
  await w.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => document.querySelector('#mwB').weaver?.readout().scans === 100, null, { timeout: 120_000 });
  const attrs = await w.evaluate((e) => Object.fromEntries(['left-clamp', 'autoplay', 'scans', 'left-strength'].map((n) => [n, e.getAttribute(n)])));
  assert.deepEqual(attrs, { 'left-clamp': '4', autoplay: 'off', scans: '100', 'left-strength': '2' });
  const core = await w.evaluate((e) => ({ clamp: e.weaver.readout().panes[0].clamp, strength: e.weaver.readout().panes[0].strength, playing: e.playing }));
  assert.deepEqual(core, { clamp: 4, strength: 2, playing: false });
  // The copied link names the strength and, as every link, what differs
  // from the defaults (the page's clamp 4)...
  await w.locator('button[name=copy-link]').click();
  await page.waitForFunction(() => document.querySelector('#mwB').dataset.link !== undefined);
  let link = new URL(await w.evaluate((e) => e.dataset.link));
  assert.equal(link.searchParams.get('mwB.left-strength'), '2');
  assert.equal(link.searchParams.get('mwB.left-clamp'), '4');
  // ...and the clamp once the reader moves it back to its default: the
  // page's own 4 would otherwise stay.
  await w.evaluate((e) => {
    const input = e.querySelector('input[name=clamp-left]');
    input.value = '12';
    input.dispatchEvent(new Event('input', { bubbles: true }));
    delete e.dataset.link;
  });
  await w.locator('button[name=copy-link]').click();
  await page.waitForFunction(() => document.querySelector('#mwB').dataset.link !== undefined);
  link = new URL(await w.evaluate((e) => e.dataset.link));
  assert.equal(link.searchParams.get('mwB.left-clamp'), '12');
  assert.deepEqual(errors, []);
  await close();
});

test('exercise 1’s link shows the prior and all ten readings in the table, none hidden in its inner scroll', async () => {
  const { page: index, close: closeIndex } = await openPage('/', { viewport: LAPTOP });
  const href = await index.getAttribute('a[data-exercise="1"]', 'href');
  await closeIndex();
  const { page, errors, close } = await openPage(`/${href}`, { viewport: LAPTOP, reducedMotion: 'reduce' });
  await page.waitForFunction(() => document.querySelectorAll('occgrid-cell-filter .cell-filter-table tbody tr').length === 11, null, { timeout: 60_000 });
  const box = await page.evaluate(() => {
    const s = document.querySelector('occgrid-cell-filter .cell-filter-scroll');
    const last = s.querySelector('tbody tr:last-child').getBoundingClientRect();
    const r = s.getBoundingClientRect();
    return { scroll: s.scrollHeight, client: s.clientHeight, lastBottom: last.bottom, boxBottom: r.bottom };
  });
  assert.ok(box.scroll <= box.client + 1, `the table scrolls inside its box: ${box.scroll} px in ${box.client}`);
  assert.ok(box.lastBottom <= box.boxBottom + 1, 'the tenth reading is inside the box');
  assert.deepEqual(errors, []);
  await close();
});

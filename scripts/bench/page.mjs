// W7 `page` (BENCHMARKS.md): the chapter page as a reader opens it, in
// Debian's headless Chromium against the project's own server. Two
// viewports: a 1280×800 desktop, and a 390×844 phone (device scale 3, touch)
// with the CPU throttled 4× through the DevTools protocol (Lighthouse's
// mobile setting). Three situations, each on a fresh page:
//
// - `load`: the page loads and nothing is scrolled, 15 s recorded;
// - `scroll`: each widget is scrolled into view, one a second, 15 s in all;
// - `play-WIDGET`: the widget scrolled into view and playing for 5 s
//   (frames per second counted with requestAnimationFrame);
// - `link-sweep` (desktop): the link that froze the tab, Map Weaver's
//   every-cell sweep in both panes over a 1024 x 1024 scene at speed 8,
//   playing for 8 s from its first scan;
// - `knob-sweep` (desktop): 20 laps (13,060 scans) integrated before the
//   first frame, then the left Mapper menu set to "Every-cell sweep",
//   recorded from the choice until the pane is rebuilt.
//
// `OCCGRID_PAGE_SITUATIONS` (a comma list of situations) and
// `OCCGRID_PAGE_VIEWPORTS` (desktop, phone) pick a part; `OCCGRID_PAGE_RUNS`
// sets the runs per line.
//
// Every main-thread task over 50 ms is a `longtask` entry (buffered from the
// page's start); total blocking time is the sum of each one's part over
// 50 ms. `all_drawn_ms` is when the last widget first drew into a canvas of
// its own (a canvas drawing call seen inside each custom element), from
// navigation start. Medians over 3 runs per line.
//
// `npm run bench -- page` prints one JSON line per viewport and situation.
import { median, round } from '../lib/stats.mjs';

const WORKLOAD = 'page';
const RUNS = Number(process.env.OCCGRID_PAGE_RUNS || 3);
const WIDGETS = ['cell-filter', 'map-weaver', 'inverse-workbench', 'sensor-fusion', 'doorway-trap'];
/** The widgets that play, and the control that starts them. */
const PLAYERS = ['map-weaver', 'sensor-fusion', 'doorway-trap'];
/** The data attribute each player sets once its run exists. */
const READY = { 'map-weaver': 'scans', 'sensor-fusion': 'step', 'doorway-trap': 'flips' };
/** The heavy Map Weaver links, desktop only: where each opens. */
const LINKS = {
  'link-sweep': '/?map-weaver.scene=' + encodeURIComponent('{"width":1024,"height":1024,"resolution":0.01171875}') +
    '&map-weaver.left-mapper=sweep&map-weaver.right-mapper=sweep&map-weaver.speed=8#map-weaver',
  'knob-sweep': '/?map-weaver.laps=20&map-weaver.scans=13060&map-weaver.autoplay=off#map-weaver',
};
const pick = (name, all) => (process.env[name] ? all.filter((x) => process.env[name].split(',').includes(x)) : all);
const VIEWPORTS = {
  desktop: { viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1, throttle: 1 },
  phone: { viewport: { width: 390, height: 844 }, deviceScaleFactor: 3, hasTouch: true, isMobile: true, throttle: 4 },
};

/** Installed before any script of the page runs. */
function instrument() {
  const w = { tasks: [], firstDraw: {}, frames: 0, counting: false };
  window.__pageBench = w;
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) w.tasks.push([e.startTime, e.duration]);
  }).observe({ type: 'longtask', buffered: true });
  const host = (canvas) => {
    for (let n = canvas; n; n = n.parentNode || n.host) {
      if (n.localName && n.localName.startsWith('occgrid-')) return n.localName;
    }
    return null;
  };
  const wrap = (proto, name) => {
    const f = proto[name];
    proto[name] = function (...args) {
      const h = this.canvas && host(this.canvas);
      if (h && w.firstDraw[h] === undefined) w.firstDraw[h] = performance.now();
      return f.apply(this, args);
    };
  };
  for (const name of ['putImageData', 'drawImage', 'fillRect', 'stroke', 'fill']) wrap(CanvasRenderingContext2D.prototype, name);
  const tick = () => {
    if (w.counting) w.frames++;
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

const summary = ({ tasks, firstDraw }, from, to, widgets) => {
  const inside = tasks.filter(([start]) => start >= from && start < to);
  const drawn = widgets.map((name) => firstDraw[name]);
  return {
    total_blocking_ms: inside.reduce((sum, [, ms]) => sum + Math.max(0, ms - 50), 0),
    long_tasks: inside.length,
    longest_task_ms: inside.length ? Math.max(...inside.map(([, ms]) => ms)) : 0,
    all_drawn_ms: drawn.every((t) => t !== undefined) ? Math.max(...drawn) : null,
  };
};

async function oneRun(browser, port, viewportName, situation) {
  const v = VIEWPORTS[viewportName];
  const context = await browser.newContext({
    viewport: v.viewport, deviceScaleFactor: v.deviceScaleFactor, hasTouch: !!v.hasTouch, isMobile: !!v.isMobile,
  });
  const page = await context.newPage();
  try {
    await page.addInitScript(instrument);
    if (v.throttle > 1) {
      const cdp = await context.newCDPSession(page);
      await cdp.send('Emulation.setCPUThrottlingRate', { rate: v.throttle });
    }
    await page.goto(`http://127.0.0.1:${port}${LINKS[situation] ?? '/'}`, { waitUntil: 'load' });
    let t0 = await page.evaluate(() => performance.now());
    let fps = null;
    const weaver = page.locator('occgrid-map-weaver').first();
    if (situation === 'link-sweep') {
      await weaver.scrollIntoViewIfNeeded();
      await page.waitForFunction(() => Number(document.querySelector('occgrid-map-weaver').dataset.scans) >= 1, null, { timeout: 120_000 });
      t0 = await page.evaluate(() => { window.__pageBench.frames = 0; window.__pageBench.counting = true; return performance.now(); });
      await page.waitForTimeout(8000);
      const r = await page.evaluate(() => ({ frames: window.__pageBench.frames, now: performance.now() }));
      fps = r.frames / ((r.now - t0) / 1000);
    } else if (situation === 'knob-sweep') {
      await weaver.scrollIntoViewIfNeeded();
      await page.waitForFunction(() => {
        const el = document.querySelector('occgrid-map-weaver');
        return el.dataset.scans === '13060' && !el.dataset.fastForward;
      }, null, { timeout: 300_000 });
      await page.waitForTimeout(500);
      t0 = await page.evaluate(() => performance.now());
      await weaver.locator('.map-weaver-left').getByLabel('Mapper, left map').selectOption('sweep');
      await page.waitForFunction(() => document.querySelector('occgrid-map-weaver .map-weaver-left').dataset.mapper === 'sweep',
        null, { timeout: 300_000, polling: 100 });
    } else if (situation === 'load') {
      await page.waitForTimeout(15_000);
    } else if (situation === 'scroll') {
      for (const name of WIDGETS) {
        await page.locator(`occgrid-${name}`).first().scrollIntoViewIfNeeded();
        await page.waitForTimeout(1000);
      }
      await page.waitForTimeout(Math.max(0, 15_000 - 1000 * WIDGETS.length));
    } else {
      const name = situation.slice('play-'.length);
      const widget = page.locator(`occgrid-${name}`).first();
      await widget.scrollIntoViewIfNeeded();
      // Autoplay starts it once its run exists; a Play button starts it
      // where autoplay is off or reduced motion holds it. Pressed before the
      // run exists, Play would do nothing, and pressed after autoplay it
      // would pause: wait for the run, then press only a Play not pressed.
      await page.waitForFunction(([tag, key]) => document.querySelector(tag)?.dataset[key] !== undefined,
        [`occgrid-${name}`, READY[name]], { timeout: 120_000 });
      await page.waitForTimeout(300);
      const play = widget.getByRole('button', { name: /^(Play|Pause)/ }).first();
      if ((await play.count()) && (await play.getAttribute('aria-pressed')) !== 'true') await play.click().catch(() => {});
      await page.evaluate(() => { window.__pageBench.frames = 0; window.__pageBench.counting = true; });
      const start = await page.evaluate(() => performance.now());
      await page.waitForTimeout(5000);
      const r = await page.evaluate(() => ({ frames: window.__pageBench.frames, now: performance.now() }));
      fps = r.frames / ((r.now - start) / 1000);
    }
    await page.waitForTimeout(200);
    const w = await page.evaluate(() => window.__pageBench);
    const from = situation === 'load' || situation === 'scroll' ? 0 : t0;
    const widgets = situation === 'load' ? [] : situation === 'scroll' ? WIDGETS.map((n) => `occgrid-${n}`) : [];
    return { ...summary(w, from, Infinity, widgets), fps };
  } finally {
    await context.close();
  }
}

export default async function (core, args) {
  // Minutes of browsing: only when asked for by name.
  if (!args.includes(WORKLOAD)) return [];
  const { chromium } = await import('playwright-core');
  const { listen } = await import('../serve.mjs');
  const { server, port } = await listen(0, {});
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--no-first-run', '--disable-quic'],
  });
  const rows = [];
  try {
    for (const viewport of pick('OCCGRID_PAGE_VIEWPORTS', Object.keys(VIEWPORTS))) {
      const links = viewport === 'desktop' ? Object.keys(LINKS) : [];
      for (const situation of pick('OCCGRID_PAGE_SITUATIONS', ['load', 'scroll', ...PLAYERS.map((p) => `play-${p}`), ...links])) {
        const runs = [];
        for (let k = 0; k < RUNS; k++) runs.push(await oneRun(browser, port, viewport, situation));
        const med = (key) => {
          const xs = runs.map((r) => r[key]).filter((x) => x !== null);
          return xs.length ? round(median(xs), 1) : null;
        };
        rows.push({
          workload: WORKLOAD, runtime: 'chromium', viewport, situation,
          total_blocking_ms: med('total_blocking_ms'), long_tasks: med('long_tasks'), longest_task_ms: med('longest_task_ms'),
          all_drawn_ms: med('all_drawn_ms'), fps: med('fps'),
        });
      }
    }
  } finally {
    await browser.close();
    await new Promise((r) => server.close(r));
  }
  return rows;
}

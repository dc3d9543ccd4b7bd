// W7 `page` (docs/BENCHMARKS.md): the chapter page as a reader opens it, in
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
// - `knobs` (desktop, only when named in `OCCGRID_PAGE_SITUATIONS`): every
//   knob, attribute and link of the chapter's widgets but the real-log
//   panel, each on a fresh page (see `KNOBS`): the longest task from the
//   change until the widget says it is done, one line per knob
//   (`situation: "knob"`, `knob: NAME`).
//
// `OCCGRID_PAGE_SITUATIONS` (a comma list of situations) and
// `OCCGRID_PAGE_VIEWPORTS` (desktop, phone) pick a part; `OCCGRID_PAGE_RUNS`
// sets the runs per line; `OCCGRID_PAGE_KNOBS` keeps the knobs whose name
// holds it.
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

/**
 * The knob audit: what each knob changes, on which page, and the state that
 * means done. `ready`, `pre`, `act` and `done` are expressions evaluated in
 * the page (`act` may also be a function of the page); `act: null` measures
 * the widget's start, scrolled to from the top of a page gone quiet.
 */
const KNOBS = (() => {
  const list = [];
  const set = (tag, name, value) => `document.querySelector('${tag}').setAttribute('${name}', ${JSON.stringify(value)})`;
  const click = (tag, name) => `document.querySelector('${tag}').querySelector('button[name=${name}]').click()`;
  const markOld = (tag, field) => `window.__old = document.querySelector('${tag}').${field}`;

  const MW = 'occgrid-map-weaver';
  const mwSettled = `(() => { const el = document.querySelector('${MW}'); if (!el?.weaver || el.dataset.fastForward) return false;
    return el.weaver.progress().behind.every((n) => n === 0) && !el.loop.running; })()`;
  const mwNewRun = `(document.querySelector('${MW}').weaver !== window.__old && ${mwSettled})`;
  const mw = (name, act, { scans = 1959, done = mwSettled, pre = null, extra = '' } = {}) => list.push({
    name: `map-weaver: ${name}`, url: `/?map-weaver.autoplay=off&map-weaver.scans=${scans}${extra}#map-weaver`, tag: MW, ready: mwSettled, pre, act, done,
  });
  const mwRun = { pre: markOld(MW, 'weaver'), done: mwNewRun };
  mw('start', null, { scans: 0 });
  mw('left-mapper sweep after 3 laps', set(MW, 'left-mapper', 'sweep'));
  mw('right-mapper sweep after 3 laps', set(MW, 'right-mapper', 'sweep'));
  mw('left-sensor cone', set(MW, 'left-sensor', 'cone'));
  mw('left-beta 40', set(MW, 'left-beta', '40'), { extra: '&map-weaver.left-sensor=cone' });
  mw('left-beams 15', set(MW, 'left-beams', '15'));
  mw('left-resolution 0.025', set(MW, 'left-resolution', '0.025'));
  mw('left-model learned', set(MW, 'left-model', 'learned'));
  mw('left-pose dead-reckoning', set(MW, 'left-pose', 'dead-reckoning'));
  mw('left-clamp 3', set(MW, 'left-clamp', '3'));
  mw('left-strength 2', set(MW, 'left-strength', '2'));
  mw('left-forget-l0 on', set(MW, 'left-forget-l0', 'on'), { extra: '&map-weaver.left-model=learned' });
  mw('person off', set(MW, 'person', 'off'));
  mw('situation ghost-watch', set(MW, 'situation', 'ghost-watch'), mwRun);
  mw('laps 5', set(MW, 'laps', '5'), mwRun);
  mw('seed 3', set(MW, 'seed', '3'), mwRun);
  mw('scene 1024 x 1024', set(MW, 'scene', '{"width":1024,"height":1024,"resolution":0.01171875}'), { scans: 0, ...mwRun });
  mw('scans 13060 (20 laps)', set(MW, 'scans', '13060'), { scans: 0, extra: '&map-weaver.laps=20', ...mwRun });
  mw('reset', click(MW, 'reset'));
  mw('step', click(MW, 'step'), { scans: 100 });
  mw('map-width 900', set(MW, 'map-width', '900'));
  mw('speed 8, playing 3 s', async (page) => {
    await page.evaluate(`${set(MW, 'speed', '8')}; ${click(MW, 'play')}`);
    await page.waitForTimeout(3000);
  }, { scans: 0, done: 'true' });

  const SF = 'occgrid-sensor-fusion';
  const sfSettled = `(() => { const el = document.querySelector('${SF}'); return !!el?.sim && el.dataset.state === 'ready'
    && el.dataset.fastForward === undefined && el.dataset.rebuilding === undefined && !el.beamTask && !el.loop.running; })()`;
  const sfPlayed = `(document.querySelector('${SF}').dataset.step === '81' && !document.querySelector('${SF}').playing)`;
  const sfRun = { pre: markOld(SF, 'sim'), done: `(document.querySelector('${SF}').sim !== window.__old && ${sfSettled})` };
  const sf = (name, act, { extra = '', done = sfSettled, pre = null } = {}) => list.push({
    name: `sensor-fusion: ${name}`, url: `/?sensor-fusion.autoplay=off${extra}#sensor-fusion`, tag: SF, ready: sfSettled, pre, act, done,
  });
  const fine = '&sensor-fusion.scene=' + encodeURIComponent('{"resolution": 0.0125}');
  sf('start', null);
  sf('lidar-beams 12 after the lap', set(SF, 'lidar-beams', '12'), { extra: '&sensor-fusion.scans=81' });
  sf('lidar-beams 720 after the lap', set(SF, 'lidar-beams', '720'), { extra: '&sensor-fusion.scans=81' });
  sf('lidar-beams 2048 after 2 laps', set(SF, 'lidar-beams', '2048'), { extra: '&sensor-fusion.scans=162&sensor-fusion.scene=' + encodeURIComponent('{"laps":2}') });
  sf('seed 3', set(SF, 'seed', '3'), sfRun);
  sf('scans 81', set(SF, 'scans', '81'), sfRun);
  sf('scene 10 laps, scans 810', `${set(SF, 'scene', '{"laps": 10}')}; ${set(SF, 'scans', '810')}`, sfRun);
  sf('scene resolution 0.0125', set(SF, 'scene', '{"resolution": 0.0125}'), sfRun);
  sf('step', click(SF, 'step'));
  sf('reset', click(SF, 'reset'), { extra: '&sensor-fusion.scans=81' });
  sf('play the lap', click(SF, 'play'), { done: sfPlayed });
  sf('play the lap at 0.0125 m', click(SF, 'play'), { extra: fine, done: sfPlayed });
  sf('map-width 900', set(SF, 'map-width', '900'));

  const DT = 'occgrid-doorway-trap';
  const dtReady = `(document.querySelector('${DT}')?.dataset.state === 'ready')`;
  const dtRun = { pre: markOld(DT, 'trap'), done: `(document.querySelector('${DT}').trap !== window.__old && ${dtReady})` };
  const dt = (name, act, { done = 'true', pre = null } = {}) => list.push({
    name: `doorway-trap: ${name}`, url: '/?doorway-trap.autoplay=off#doorway-trap', tag: DT, ready: dtReady, pre, act, done,
  });
  dt('start', null);
  dt('seed 3', set(DT, 'seed', '3'), dtRun);
  dt('scans 4096', set(DT, 'scans', '4096'), dtRun);
  dt('flips 100000', set(DT, 'flips', '100000'), dtRun);
  dt('scene prior 0.3', set(DT, 'scene', '{"prior": 0.3}'), dtRun);
  dt('scene resolution 0.01', set(DT, 'scene', '{"resolution": 0.01}'), dtRun);
  dt('arrangement collinear', set(DT, 'arrangement', 'collinear'));
  dt('cells', set(DT, 'cells', '1.5, 0, 2, 5'));
  dt('reading 1.5', set(DT, 'reading', '1.5'));
  dt('prior 0.3', set(DT, 'prior', '0.30'));
  dt('ten MAP steps', `for (let i = 0; i < 10; i++) ${click(DT, 'map-step')}`);
  dt('both halves playing 4 s', async (page) => {
    await page.evaluate(`${click(DT, 'sweep-play')}; ${click(DT, 'map-play')}`);
    await page.waitForTimeout(4000);
  });
  dt('map-width 900', set(DT, 'map-width', '900'));

  const IW = 'occgrid-inverse-workbench';
  const iwTrained = (key, value) => `(document.querySelector('${IW}').dataset.${key} === '${value}' && !document.querySelector('${IW}').retrainButton.disabled)`;
  const iw = (name, act, done) => list.push({
    name: `inverse-workbench: ${name}`, url: '/#inverse-workbench', tag: IW, ready: iwTrained('state', 'ready'), act, done,
  });
  iw('start', null, 'true');
  iw('reading 6', set(IW, 'reading', '6'), `document.querySelector('${IW}').dataset.reading === '6'`);
  iw('zoom on', set(IW, 'zoom', 'on'), 'true');
  iw('seed 3', set(IW, 'seed', '3'), iwTrained('seed', '3'));
  iw('density 0.45', set(IW, 'density', '0.45'), iwTrained('density', '0.45'));

  const CF = 'occgrid-cell-filter';
  const many = 'of'.repeat(500);
  const cf = (name, act, query = '') => list.push({
    name: `cell-filter: ${name}`, url: `/?${query}#cell-filter`, tag: CF, ready: `document.querySelector('${CF}')?.ready === true`, act, done: 'true',
  });
  cf('readings 1000', set(CF, 'readings', many));
  cf('p-occ 0.9 over 1000 readings', set(CF, 'p-occ', '0.9'), `cell-filter.readings=${many}`);
  cf('clamp off over 1000 readings', set(CF, 'clamp', 'off'), `cell-filter.readings=${many}`);
  cf('forget-l0 on', set(CF, 'forget-l0', 'on'));
  return list;
})();

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

/**
 * One knob on a fresh desktop page: the longest main-thread task from the
 * change (or, for a start, from the scroll) until its done state holds and
 * half a second more.
 */
async function oneKnob(browser, port, knob) {
  // The page's policy allows no string evaluation; the audit's own
  // expressions are the page's test harness, not its code.
  const context = await browser.newContext({ viewport: VIEWPORTS.desktop.viewport, bypassCSP: true });
  const page = await context.newPage();
  try {
    await page.addInitScript(instrument);
    const starting = knob.act === null;
    await page.goto(`http://127.0.0.1:${port}${starting ? knob.url.replace(/#.*$/, '') : knob.url}`, { waitUntil: 'load' });
    if (starting) await page.waitForTimeout(4000);
    let t0 = await page.evaluate(() => performance.now());
    await page.locator(knob.tag).first().scrollIntoViewIfNeeded();
    if (!starting) {
      await page.waitForFunction(knob.ready, null, { timeout: 300_000, polling: 100 });
      await page.waitForTimeout(700);
      if (knob.pre) await page.evaluate(knob.pre);
      t0 = await page.evaluate(() => performance.now());
      if (typeof knob.act === 'function') await knob.act(page);
      else await page.evaluate(knob.act);
    }
    await page.waitForFunction(starting ? knob.ready : knob.done, null, { timeout: 300_000, polling: 100 });
    await page.waitForTimeout(500);
    const { tasks } = await page.evaluate(() => window.__pageBench);
    return summary({ tasks, firstDraw: {} }, t0, Infinity, []).longest_task_ms;
  } finally {
    await context.close();
  }
}

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
    const named = (process.env.OCCGRID_PAGE_SITUATIONS || '').split(',');
    if (named.includes('knobs') && pick('OCCGRID_PAGE_VIEWPORTS', ['desktop']).length) {
      for (const knob of KNOBS.filter((k) => k.name.includes(process.env.OCCGRID_PAGE_KNOBS || ''))) {
        const runs = [];
        for (let k = 0; k < RUNS; k++) runs.push(await oneKnob(browser, port, knob));
        rows.push({
          workload: WORKLOAD, runtime: 'chromium', viewport: 'desktop', situation: 'knob', knob: knob.name,
          longest_task_ms: round(median(runs), 1),
        });
      }
    }
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

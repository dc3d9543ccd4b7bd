// A huge attribute value is refused on its length (docs/ARCHITECTURE.md,
// "Bad input"): a page or a link that sets a megabyte in any attribute of
// any widget gets a refusal naming the attribute with a short prefix of
// the value, and the page's main thread is never held for long. Every
// attribute of every widget's table (its `attributeSpec`) is set at once,
// to a megabyte of letters and to 100,000 opening brackets, and so is one
// attribute no widget knows.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { baseUrl, openPage, serveForeign, shutdown } from './harness.mjs';

const WIDGETS = ['cell-filter', 'doorway-trap', 'inverse-workbench', 'map-weaver', 'sensor-fusion'];
/** The longest main-thread task the issue allows, ms. */
const LONGEST_TASK_MS = 200;
/** The most of a value a refusal may repeat: 60 characters and an ellipsis, as the core's messages. */
const PREFIX = 60;

let project;
let course;

before(async () => {
  project = await baseUrl();
  const body = WIDGETS.map((w) => `<occgrid-${w}></occgrid-${w}>`).join('\n');
  const scripts = WIDGETS.map((w) => `<script type="module" src="${project}/widgets/${w}.js"></script>`).join('\n');
  course = await serveForeign({
    '/all.html': `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>Every widget</title><link rel="icon" href="data:,"></head>
<body><h1>Every widget</h1>${body}${scripts}</body></html>
`,
  });
});

after(async () => {
  await course?.close();
  await shutdown();
});

/** Every widget has read its attributes against the core's bounds. */
const allResolved = (page) => page.waitForFunction((tags) => tags.every((t) => {
  const el = document.querySelector(`occgrid-${t}`);
  const spec = customElements.get(`occgrid-${t}`)?.attributeSpec;
  return el?.core && el.values && spec && Object.values(spec).every((s) => !s.core || s.fromCore);
}), WIDGETS, { timeout: 120_000 });

for (const [label, value] of [['a megabyte of letters', 'x'.repeat(1_000_000)], ['100,000 opening brackets', '['.repeat(100_000)]]) {
  test(`${label} in every attribute of every widget: refused by name, briefly, with no long task`, async (t) => {
    const { page, logs, close } = await openPage(`${course.origin}/all.html`);
    try {
      await allResolved(page);
      await page.evaluate(() => {
        window.__longTasks = [];
        window.__observer = new PerformanceObserver((list) => {
          for (const e of list.getEntries()) window.__longTasks.push(e.duration);
        });
        window.__observer.observe({ type: 'longtask' });
      });
      const char = value[0];
      for (const tag of WIDGETS) {
        const names = await page.evaluate(([t, v]) => {
          const el = document.querySelector(`occgrid-${t}`);
          const names = Object.keys(customElements.get(`occgrid-${t}`).attributeSpec);
          for (const n of names) el.setAttribute(n, v);
          el.setAttribute('no-such-attribute', v);
          return names;
        }, [tag, value]);
        // Done: the widget's error box names every attribute, its notice the unknown one.
        await page.waitForFunction(([t, ns]) => {
          const el = document.querySelector(`occgrid-${t}`);
          const box = el.querySelector(':scope > .occgrid-attribute-error');
          const notice = el.querySelector(':scope > .occgrid-attribute-warning');
          return box && notice?.textContent.includes('no-such-attribute') && ns.every((n) => box.textContent.includes(`invalid ${n}:`));
        }, [tag, names], { timeout: 60_000 });
        const shown = await page.evaluate((t) => {
          const el = document.querySelector(`occgrid-${t}`);
          return [...el.querySelectorAll(':scope > .occgrid-attribute-error, :scope > .occgrid-attribute-warning, :scope > .occgrid-error')]
            .map((b) => b.textContent);
        }, tag);
        const text = shown.join('\n');
        assert.ok(text.length < 400 * (names.length + 2), `${tag}: the boxes hold ${text.length} characters`);
        assert.ok(!text.includes(char.repeat(PREFIX + 1)), `${tag}: a box repeats more than ${PREFIX} characters of the value`);
        for (const n of names) {
          const line = text.split('\n').join('').includes(`invalid ${n}: "${char.repeat(PREFIX)}…"`)
            || new RegExp(`invalid ${n}: [^"]*\\d`).test(text);
          assert.ok(line, `${tag}: the refusal of ${n} shows a prefix of the value (or its length): ${text.slice(0, 2000)}`);
        }
      }
      const longest = await page.evaluate(() => {
        for (const e of window.__observer.takeRecords()) window.__longTasks.push(e.duration);
        return Math.max(0, ...window.__longTasks);
      });
      t.diagnostic(`longest main-thread task: ${Math.round(longest)} ms`);
      assert.ok(longest < LONGEST_TASK_MS, `the longest main-thread task took ${Math.round(longest)} ms`);
      const longLogs = logs.filter((l) => l.text.length > 2000);
      assert.deepEqual(longLogs.map((l) => l.text.slice(0, 200)), [], 'a console message repeats the value');
    } finally {
      await close();
    }
  });
}

test('a scene nested 4,990 deep, under the length cap, is refused by name before it is parsed', async () => {
  const { page, close } = await openPage(`${course.origin}/all.html`);
  try {
    await allResolved(page);
    const deep = `{"a": ${'['.repeat(4990)}${']'.repeat(4990)}}`;
    for (const tag of ['doorway-trap', 'map-weaver', 'sensor-fusion']) {
      await page.evaluate(([t, v]) => document.querySelector(`occgrid-${t}`).setAttribute('scene', v), [tag, deep]);
      const box = page.locator(`occgrid-${tag} > .occgrid-attribute-error`);
      await box.waitFor();
      const text = await box.textContent();
      assert.match(text, /^invalid scene: "\{"a": \[{54}…" \(expected a JSON object such as .*, nested at most 16 deep\)$/);
    }
  } finally {
    await close();
  }
});

// A server refuses a request line of a megabyte (Node's own does), but
// another may serve it, and a page's script may put it in the URL: the
// link is written into the page's URL and two more widgets are added, which
// read it as they start (widgets/lib/state.js, restoreFromUrl).
test('a link with a megabyte in an attribute is refused by name with a short prefix, with no long task', async (t) => {
  const huge = 'x'.repeat(1_000_000);
  const { page, logs, close } = await openPage(`${course.origin}/all.html`);
  try {
    await allResolved(page);
    // The page's own step, in a task of its own: not the widgets' doing.
    await page.evaluate((v) => history.replaceState(null, '', `?linked-weaver.scene=${v}&linked-filter.readings=${v}`), huge);
    await page.evaluate(() => {
      window.__longTasks = [];
      window.__observer = new PerformanceObserver((list) => {
        for (const e of list.getEntries()) window.__longTasks.push(e.duration);
      });
      window.__observer.observe({ type: 'longtask' });
      document.body.append(Object.assign(document.createElement('occgrid-map-weaver'), { id: 'linked-weaver' }));
      document.body.append(Object.assign(document.createElement('occgrid-cell-filter'), { id: 'linked-filter' }));
    });
    for (const [id, name] of [['linked-weaver', 'scene'], ['linked-filter', 'readings']]) {
      const box = page.locator(`#${id} > .occgrid-attribute-error`);
      await box.waitFor();
      const text = await box.textContent();
      assert.ok(text.startsWith(`invalid ${name}: "${'x'.repeat(PREFIX)}…" (1,000,000 characters, at most `), text);
      assert.ok(text.length < 400, text);
    }
    const longest = await page.evaluate(() => {
      for (const e of window.__observer.takeRecords()) window.__longTasks.push(e.duration);
      return Math.max(0, ...window.__longTasks);
    });
    t.diagnostic(`longest main-thread task: ${Math.round(longest)} ms`);
    assert.ok(longest < LONGEST_TASK_MS, `the longest main-thread task took ${Math.round(longest)} ms`);
    assert.deepEqual(logs.filter((l) => l.text.length > 2000).map((l) => l.text.slice(0, 200)), []);
  } finally {
    await close();
  }
});

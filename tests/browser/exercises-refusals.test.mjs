// Every widget shows every refusal inside itself, where an instructor who
// embeds it looks, not only in the console: a misspelt scene field, a bad
// attribute value, a seed box left empty. Each widget is embedded alone on
// a course page of another origin, as the README's Embedding section has
// it, and the refusal is read off the widget.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { baseUrl, openPage, screenshot, serveForeign, shutdown } from './harness.mjs';

after(shutdown);

/** Opens a course page holding `html`, with the script of widget `name`. */
async function embed(name, html) {
  const project = await baseUrl();
  const foreign = await serveForeign({
    '/course.html': `<!doctype html><html lang="en"><head><meta charset="utf-8"><title>Course page</title><link rel="icon" href="data:,"></head>
<body><h1>Week 9</h1>${html}<script type="module" src="${project}/widgets/${name}.js"></script></body></html>`,
  });
  const opened = await openPage(`${foreign.origin}/course.html`, { reducedMotion: 'reduce' });
  return { ...opened, close: async () => { await opened.close(); await foreign.close(); } };
}

/**
 * Waits until `tag` shows, inside itself and on screen, an error whose text
 * holds `needle`, and returns that text.
 */
async function refusalShown(page, tag, needle) {
  await page.locator(tag).scrollIntoViewIfNeeded();
  const handle = await page.waitForFunction(([t, n]) => {
    const box = [...document.querySelector(t).querySelectorAll('.occgrid-error, [role=alert]')]
      .find((e) => e.textContent.includes(n) && e.checkVisibility());
    return box ? box.textContent : null;
  }, [tag, needle], { timeout: 30_000 });
  return handle.jsonValue();
}

const SCENE = '{"bogus_field":1}';

test('doorway trap: a misspelt scene field is shown inside the widget, and the panes stop saying "Loading…"', async () => {
  const tag = 'occgrid-doorway-trap';
  const { page, errors, close } = await embed('doorway-trap', `<${tag} scene='${SCENE}'></${tag}>`);
  const text = await refusalShown(page, tag, 'unknown field "bogus_field"');
  assert.match(text, /^invalid scene: unknown field "bogus_field" \(expected min_x, min_y, /);
  // The two-cell table below does not depend on the scene and draws; its
  // answer does not clear the scene's refusal.
  await page.waitForFunction((t) => document.querySelectorAll(`${t} .doorway-trap-joint tbody tr`).length === 4, tag);
  assert.equal(await page.locator(`${tag} > .occgrid-error`).textContent(), text, 'still shown once the table has drawn');
  await page.waitForFunction((t) => document.querySelector(t).dataset.state === 'refused', tag);
  const statuses = await page.locator(`${tag} .doorway-trap-status`).allTextContents();
  assert.deepEqual(statuses, Array(2).fill('No map: the scene was refused (see the message above).'));
  assert.equal(await page.locator(tag).evaluate((el) => el.textContent.includes('Loading…')), false);
  await screenshot(page.locator(tag), 'refusal-doorway-trap-scene');
  assert.deepEqual(errors, [`${tag}: ${text}`]);
  await close();
});

test('sensor fusion: a misspelt scene field is shown inside the widget, and its status says there is no map', async () => {
  const tag = 'occgrid-sensor-fusion';
  const { page, errors, close } = await embed('sensor-fusion', `<${tag} scene='${SCENE}'></${tag}>`);
  const text = await refusalShown(page, tag, 'unknown field "bogus_field"');
  assert.match(text, /^invalid scene: unknown field "bogus_field" \(expected room, /);
  await page.waitForFunction((t) => document.querySelector(t).dataset.state === 'refused', tag);
  assert.equal(await page.locator(`${tag} .sensor-fusion-status`).textContent(), 'No maps: the scene was refused (see the message above).');
  assert.deepEqual(errors, [`${tag}: ${text}`]);
  await close();
});

test('inverse workbench: a bad seed attribute and an empty seed box are refused inside the widget, by name', async () => {
  const tag = 'occgrid-inverse-workbench';
  const { page, errors, close } = await embed('inverse-workbench', `<${tag} seed="abc"></${tag}>`);
  const attr = await refusalShown(page, tag, 'invalid seed');
  assert.equal(attr, 'invalid seed: "abc" (expected a whole number from 0 to 9007199254740991)');
  await page.waitForFunction((t) => document.querySelector(t).dataset.state === 'ready', tag, { timeout: 30_000 });
  await page.locator(tag).getByLabel('Seed').fill('');
  await page.locator(tag).getByRole('button', { name: 'Retrain' }).click();
  const box = await refusalShown(page, tag, 'Seed box');
  assert.equal(box, 'Seed box: invalid seed: "" (expected a whole number from 0 to 9007199254740991); the model trained with seed 9 stays.');
  assert.equal(errors.length, 2);
  await close();
});

test('cell filter: bad readings and a bad clamp are refused inside the widget, by name', async () => {
  const tag = 'occgrid-cell-filter';
  const { page, errors, close } = await embed('cell-filter', `<${tag} readings="oxo" clamp="-1"></${tag}>`);
  const text = await refusalShown(page, tag, 'invalid clamp');
  assert.match(text, /invalid readings: "oxo" \(expected at most 1,000 letters o for occupied and f for free, e\.g\. "oof"\)/);
  assert.match(text, /invalid clamp: "-1" \(expected a number from 1 to 30 in steps of 0\.5 \(log odds\), or "off" for no clamp\)/);
  await page.locator(tag).evaluate((el) => el.setAttribute('readings', 'o'.repeat(1001)));
  assert.match(await refusalShown(page, tag, '1,001 readings'), /invalid readings: 1,001 readings \(expected at most 1,000 letters/);
  assert.ok(errors.length >= 2 && errors.every((e) => e.startsWith(`${tag}: invalid `)), errors.join('\n'));
  await close();
});

test('Map Weaver: a misspelt scene field is shown inside the widget', async () => {
  const tag = 'occgrid-map-weaver';
  const { page, errors, close } = await embed('map-weaver', `<${tag} scene='${SCENE}'></${tag}>`);
  const text = await refusalShown(page, tag, 'unknown field "bogus_field"');
  assert.match(text, /invalid .*scene: unknown field "bogus_field"/);
  assert.ok(errors.some((e) => e.includes('unknown field "bogus_field"')), errors.join('\n'));
  await close();
});

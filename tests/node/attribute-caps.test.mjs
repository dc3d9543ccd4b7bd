// A value's length is bounded before it is parsed, and a refusal quotes at
// most 60 characters of it (widgets/lib/attributes.js, parseBounded and
// shortText): a page or a link may set a megabyte in any attribute.
import test from 'node:test';
import assert from 'node:assert/strict';
import {
  MAX_JSON_DEPTH, MAX_JSON_TEXT, SHORT_TEXT, controlGroups, flag, jsonObject, oneOf, parseBounded, shortText, whole,
} from '../../widgets/lib/attributes.js';

test('a refusal quotes at most 60 characters of the value, then an ellipsis', () => {
  assert.equal(shortText('abc'), 'abc');
  assert.equal(shortText('x'.repeat(60)), 'x'.repeat(60));
  assert.equal(shortText('x'.repeat(61)), `${'x'.repeat(60)}…`);
  const seed = whole(0, 10);
  assert.throws(() => seed.parse('9'.repeat(150), 'seed'), (e) => e.message === `invalid seed: "${'9'.repeat(60)}…" (expected ${seed.describe})`);
  // A short value is quoted whole, as before.
  assert.throws(() => seed.parse('11', 'seed'), (e) => e.message === `invalid seed: "11" (expected ${seed.describe})`);
  const groups = controlGroups(['sliders', 'link']);
  assert.throws(() => groups.parse(`${'y'.repeat(100)} z w v`, 'controls'), (e) => {
    assert.ok(!e.message.includes('y'.repeat(61)), e.message);
    assert.match(e.message, /unknown groups "y{60}…", "z", "w", …;/);
    return true;
  });
});

test('a value longer than its kind allows is refused unread, with its length and the cap', () => {
  const types = [whole(0, 10), flag(), oneOf(['on', 'off']), jsonObject('{"laps": 2}'), controlGroups(['sliders', 'link'])];
  for (const type of types) {
    const max = type.maxLength ?? SHORT_TEXT;
    const text = 'x'.repeat(1_000_000);
    // A parse that read the value would fail the same way; the stand-in proves it was not called.
    const unread = { ...type, parse: () => assert.fail('parsed a value past its cap') };
    assert.throws(() => parseBounded(unread, text, 'name'), (e) => {
      assert.equal(e.message, `invalid name: "${'x'.repeat(60)}…" (1,000,000 characters, at most ${max.toLocaleString('en-US')}; expected ${type.describe})`);
      return true;
    });
  }
  assert.equal(parseBounded(whole(0, 10), ' 7 ', 'seed'), 7);
  assert.equal(jsonObject('{}').maxLength, MAX_JSON_TEXT);
});

test('a JSON scene nested deeper than a scene is refused before JSON.parse', () => {
  const scene = jsonObject('{"laps": 2}');
  const nested = (n) => `{"a": ${'['.repeat(n)}${']'.repeat(n)}}`;
  assert.deepEqual(scene.parse(nested(MAX_JSON_DEPTH - 1), 'scene').a.length, 1);
  assert.throws(() => scene.parse(nested(MAX_JSON_DEPTH), 'scene'), /invalid scene: .*nested at most 16 deep/);
  assert.throws(() => scene.parse(nested(4000), 'scene'), /invalid scene: .*nested at most 16 deep/);
  // Brackets inside a string are text, not nesting.
  assert.deepEqual(scene.parse(`{"name": "${'['.repeat(100)}\\"${'{'.repeat(100)}"}`, 'scene').name.length, 201);
  assert.deepEqual(scene.parse('{"sonar": {"beta_deg": 30}}', 'scene'), { sonar: { beta_deg: 30 } });
});

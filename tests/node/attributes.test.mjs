// How the widgets read their attributes (widgets/lib/attributes.js), the
// part a page or a shared link controls: numbers are read as the decimal
// text they show (a link's `seed=0x10` is not 16, nor `1e3` 1000), and an
// attribute the widget does not declare is reported as unknown whatever
// its name, `constructor` and `__proto__` included (`in` found those on
// every object's prototype, so they passed unreported while `sede` was
// reported). Runs under Node with a stand-in for the few DOM calls the
// reader makes.
import test from 'node:test';
import assert from 'node:assert/strict';
import { AttributeReader, number, probability, whole } from '../../widgets/lib/attributes.js';

/** Asserts that `type` refuses `text` as attribute `name`, in the widgets' words. */
function refusesText(type, text, name) {
  assert.throws(() => type.parse(text, name), (e) => {
    assert.equal(e.message, `invalid ${name}: "${text}" (expected ${type.describe})`);
    return true;
  }, `${name}="${text}" should be refused`);
}

test('a whole number is decimal digits: hex, binary, octal, exponents and Infinity are refused by the attribute\'s name', () => {
  const seed = whole(0, Number.MAX_SAFE_INTEGER);
  for (const text of ['0x10', '1e3', '0b11', '0o7', 'Infinity', '', '  ', '1.5', '1.', '+5', '5 5', '١٢']) {
    refusesText(seed, text, 'seed');
  }
  assert.equal(seed.parse('16', 'seed'), 16);
  assert.equal(seed.parse(' 16 ', 'seed'), 16);
  assert.equal(seed.parse('007', 'seed'), 7);
  assert.ok(Object.is(seed.parse('-0', 'seed'), 0), '-0 reads as 0');
  assert.equal(seed.parse(String(Number.MAX_SAFE_INTEGER), 'seed'), Number.MAX_SAFE_INTEGER);
  // `left-beams=0x10` reached the core as 16 and came back under the
  // core's name ("panes[0].beams: 16"); it is the attribute's now.
  refusesText(whole(1, 4096), '0x10', 'left-beams');
  const laps = whole(1, 20);
  refusesText(laps, '-3', 'laps');
  refusesText(laps, '21', 'laps');
});

test('a number is plain decimal: exponents and hex are refused, steps still hold', () => {
  const clamp = number(1, 16, { step: 0.5 });
  for (const text of ['1e1', '0x4', 'Infinity', '', '12.5.1', '--2']) refusesText(clamp, text, 'left-clamp');
  assert.equal(clamp.parse('12', 'left-clamp'), 12);
  assert.equal(clamp.parse('2.50', 'left-clamp'), 2.5);
  refusesText(clamp, '2.25', 'left-clamp');
  const lFree = number(-3, -0.05, { step: 0.05 });
  assert.equal(lFree.parse('-0.40', 'log-l-free'), -0.4);
  assert.equal(number(0, 1).parse('.5', 'x'), 0.5);
  const p = probability({ min: 0.01, max: 0.99, step: 0.01 });
  for (const text of ['7e-1', '0x1', '']) refusesText(p, text, 'p-occ');
  assert.equal(p.parse('0.70', 'p-occ'), 0.7);
});

/** A host element with `attributes`, and the DOM calls the reader's report boxes make. */
function fakeHost(attributes) {
  const node = () => ({ className: '', setAttribute() {}, append() {}, replaceChildren() {}, after() {}, remove() {}, addEventListener() {} });
  globalThis.window ??= {};
  globalThis.document ??= { createElement: node };
  return {
    localName: 'occgrid-test',
    getAttributeNames: () => Object.keys(attributes),
    getAttribute: (n) => (Object.hasOwn(attributes, n) ? attributes[n] : null),
    querySelector: () => null,
    prepend() {},
  };
}

test('an attribute the widget does not declare is reported, whatever its name', () => {
  const spec = { seed: { type: whole(0, 100), default: '1', doc: 'the seed' } };
  const warnings = [];
  const warn = console.warn;
  console.warn = (m) => warnings.push(m);
  try {
    // HTML lowercases attribute names: `constructor` and `__proto__` are
    // the names of Object.prototype a page can write.
    const host = fakeHost({ seed: '3', sede: '4', constructor: 'x', ['__proto__']: 'y', id: 'a', 'data-x': '1', 'aria-label': 'l' });
    const reader = new AttributeReader(host, spec);
    assert.deepEqual(reader.unknown(), ['sede', 'constructor', '__proto__']);
    assert.equal(reader.read().seed, 3);
    for (const name of ['sede', 'constructor', '__proto__']) {
      assert.ok(warnings.some((w) => w.startsWith(`occgrid-test: unknown attribute ${name}=`)), `${name} is reported: ${JSON.stringify(warnings)}`);
    }
  } finally {
    console.warn = warn;
  }
});

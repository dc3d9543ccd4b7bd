// How the widgets read their HTML attributes. Each widget declares its
// attributes once, as a table of name → { type, default, doc }; this module
// parses them, keeps the last good value of each, and reports a bad value
// or an attribute the widget does not know inside the widget (and in the
// console) instead of leaving a blank box. The same table feeds the
// widget's "Copy link" state (widgets/lib/state.js), the `controls`
// attribute that hides groups of controls, and the README's list.
//
// Usage in a widget:
//   static attributeSpec = { seed: { type: whole(0, MAX), default: '1', doc: '…' }, … };
//   static observedAttributes = Object.keys(MyElement.attributeSpec);
//   this.attrs = new AttributeReader(this, MyElement.attributeSpec);
//   const values = this.attrs.read();   // every name → parsed value (default when absent)
//
// An attribute whose bounds or default are the model's (a sensor's range,
// a scene's cap) says so with `core: (constants) => ({ type, default })`,
// read from the core's `constants()`. Until the widget has the core and
// calls `this.attrs.resolve(constants)`, its value is read with the
// table's own `type` (a looser one) and a bad value is not yet reported;
// after, the core's type checks it and a bad value is reported as any other.
import { el, grouped } from './ui.js';

/**
 * Attributes every HTML element may carry; never reported as unknown. So
 * are `data-*`, `aria-*` and event handlers (`on*`).
 */
const GLOBAL_ATTRIBUTES = new Set([
  'id', 'class', 'style', 'hidden', 'title', 'lang', 'dir', 'tabindex', 'slot', 'part', 'is', 'role',
  'inert', 'nonce', 'autofocus', 'draggable', 'spellcheck', 'translate', 'contenteditable', 'accesskey',
  'autocapitalize', 'enterkeyhint', 'inputmode', 'popover', 'exportparts', 'itemscope', 'itemtype',
  'itemprop', 'itemid', 'itemref', 'writingsuggestions',
]);

const isGlobal = (name) =>
  GLOBAL_ATTRIBUTES.has(name) || name.startsWith('data-') || name.startsWith('aria-') || name.startsWith('on');

/**
 * The most of a value a message repeats: its first 60 characters and an
 * ellipsis, as the core cuts its own messages (docs/ARCHITECTURE.md, "Bad
 * input"). A page or a link may set a megabyte in an attribute; an error
 * box that repeats it all holds the page for seconds.
 */
export const SHOWN_CHARS = 60;

/** `text` as a message quotes it: at most `SHOWN_CHARS` characters, then "…". */
export function shortText(text) {
  return text.length > SHOWN_CHARS ? `${text.slice(0, SHOWN_CHARS)}…` : text;
}

/** The message every widget shows for a bad value. */
export function invalidValue(name, text, expected) {
  return new Error(`invalid ${name}: "${shortText(text)}" (expected ${expected})`);
}

/**
 * The longest text read for a value of each kind, checked before the value
 * is parsed (so that nothing trims, splits, scans or parses a megabyte): a
 * number, a flag or a word fits in `SHORT_TEXT`; a type may state its own
 * (`maxLength`: a JSON scene, a list of readings, the control groups).
 */
export const SHORT_TEXT = 200;

/** The refusal of a value longer than its kind allows, before it is parsed. */
export function tooLong(name, text, type, max) {
  return new Error(`invalid ${name}: "${shortText(text)}" (${grouped(text.length)} characters, at most ${grouped(max)}; expected ${type.describe})`);
}

/** Parses `text` with `type`, refusing it unread when it is longer than the type allows. */
export function parseBounded(type, text, name) {
  const max = type.maxLength ?? SHORT_TEXT;
  if (text.length > max) throw tooLong(name, text, type, max);
  return type.parse(text, name);
}

// ---- value types ----------------------------------------------------------
// Each type is `{ describe, parse(text, name) }`: `describe` completes
// "expected …" and `parse` returns the value or throws `invalidValue`.

/** Whole numbers and decimals as a page writes them: digits, a sign, a point. */
const WHOLE_TEXT = /^-?\d+$/;
const DECIMAL_TEXT = /^-?(\d+(\.\d*)?|\.\d+)$/;

/**
 * The number `text` writes in plain decimal (surrounding spaces allowed),
 * or NaN. `Number` alone also reads "0x10" as 16, "1e3" as 1000, "0b11",
 * "Infinity" and the empty string as 0: a link or a page would then set a
 * value other than the one its text shows.
 */
function decimal(text, pattern = DECIMAL_TEXT) {
  const t = text.trim();
  // `+ 0` turns "-0" into 0.
  return pattern.test(t) ? Number(t) + 0 : NaN;
}

/** A whole number in [min, max], written in decimal digits. */
export function whole(min, max) {
  const describe = `a whole number from ${min} to ${max}`;
  return {
    describe,
    parse(text, name) {
      const v = decimal(text, WHOLE_TEXT);
      if (!Number.isInteger(v) || v < min || v > max) throw invalidValue(name, text, describe);
      return v;
    },
  };
}

/**
 * A number in [min, max]; with `step`, one of min, min + step, … (what the
 * widget's slider can show). `unit` is named in the description.
 */
export function number(min, max, { step, unit = '' } = {}) {
  const u = unit ? ` ${unit}` : '';
  const describe = `a number from ${min} to ${max}${u}${step ? ` in steps of ${step}` : ''}`;
  return {
    describe,
    parse(text, name) {
      const v = decimal(text);
      let ok = Number.isFinite(v) && v >= min && v <= max;
      if (ok && step) {
        const k = (v - min) / step;
        ok = Math.abs(k - Math.round(k)) < 1e-6;
      }
      if (!ok) throw invalidValue(name, text, describe);
      return v;
    },
  };
}

/** Any number: an attribute's type until the core's bounds are known. */
export const ANY_NUMBER = number(-Number.MAX_VALUE, Number.MAX_VALUE);

/** A number on a slider's steps `{ min, max, step }` (the core's `constants().limits`). */
export function steps({ min, max, step }, unit) {
  return number(min, max, { step, unit });
}

/** A probability strictly between 0 and 1 (optionally on a slider's steps). */
export function probability({ min = 0, max = 1, step } = {}) {
  const inner = number(min, max, { step });
  const describe = `a probability strictly between 0 and 1${min > 0 || max < 1 ? ` (from ${min} to ${max}${step ? ` in steps of ${step}` : ''})` : ''}`;
  return {
    describe,
    parse(text, name) {
      const v = decimal(text);
      if (!(v > 0 && v < 1)) throw invalidValue(name, text, describe);
      try {
        return inner.parse(text, name);
      } catch {
        throw invalidValue(name, text, describe);
      }
    },
  };
}

/** One of a list of words; `map` turns the word into the value. */
export function oneOf(words, map = (w) => w) {
  const describe = words.length === 2 ? `"${words[0]}" or "${words[1]}"` : `one of ${words.map((w) => `"${w}"`).join(', ')}`;
  return {
    describe,
    parse(text, name) {
      const w = text.trim();
      if (!words.includes(w)) throw invalidValue(name, text, describe);
      return map(w);
    },
  };
}

/** On or off: present and empty, "on" or "true" mean on; "off" or "false" off. */
export function flag() {
  const describe = '"on" or "off"';
  return {
    describe,
    parse(text, name) {
      const w = text.trim().toLowerCase();
      if (w === '' || w === 'on' || w === 'true') return true;
      if (w === 'off' || w === 'false') return false;
      throw invalidValue(name, text, describe);
    },
  };
}

/**
 * A JSON scene's longest text, characters: a scene overrides a few dozen
 * fields (the chapter's scenes fit in a few hundred characters), so ten
 * thousand is well above any real one.
 */
export const MAX_JSON_TEXT = 10_000;
/** A JSON scene's deepest nesting: a scene's fields are numbers, pairs and small tables. */
export const MAX_JSON_DEPTH = 16;

/** How deep `text` nests brackets and braces outside its strings (a JSON text's nesting). */
function jsonDepth(text) {
  let depth = 0;
  let deepest = 0;
  let inString = false;
  for (let i = 0; i < text.length; i++) {
    const c = text.charCodeAt(i);
    if (inString) {
      if (c === 0x5c) i++; // a backslash: the next character is escaped
      else if (c === 0x22) inString = false;
    } else if (c === 0x22) inString = true;
    else if (c === 0x5b || c === 0x7b) deepest = Math.max(deepest, ++depth);
    else if (c === 0x5d || c === 0x7d) depth--;
  }
  return deepest;
}

/** A JSON object, handed to the core as it is (the core checks its fields). */
export function jsonObject(example) {
  const describe = `a JSON object such as ${example}`;
  return {
    describe,
    maxLength: MAX_JSON_TEXT,
    parse(text, name) {
      if (text.length > MAX_JSON_TEXT) throw tooLong(name, text, this, MAX_JSON_TEXT);
      if (jsonDepth(text) > MAX_JSON_DEPTH) throw invalidValue(name, text, `${describe}, nested at most ${MAX_JSON_DEPTH} deep`);
      let v;
      try {
        v = JSON.parse(text);
      } catch {
        throw invalidValue(name, text, describe);
      }
      if (v === null || typeof v !== 'object' || Array.isArray(v)) throw invalidValue(name, text, describe);
      return v;
    },
  };
}

/**
 * The `controls` attribute: which groups of controls a widget shows —
 * "all", "none", or group names separated by spaces or commas. The value
 * is a Set of group names.
 */
export function controlGroups(groups) {
  const describe = `"all", "none" or any of: ${groups.join(', ')}`;
  return {
    describe,
    groups,
    // Every group named twice, with a separator each.
    maxLength: Math.max(SHORT_TEXT, 2 * groups.reduce((n, g) => n + g.length + 2, 0)),
    parse(text, name) {
      const words = text.trim().toLowerCase().split(/[\s,]+/).filter(Boolean);
      if (words.length === 1 && words[0] === 'all') return new Set(groups);
      if (words.length === 0 || (words.length === 1 && words[0] === 'none')) return new Set();
      const unknown = words.filter((w) => !groups.includes(w));
      if (unknown.length) {
        const named = unknown.slice(0, 3).map((w) => `"${shortText(w)}"`).join(', ') + (unknown.length > 3 ? ', …' : '');
        throw new Error(`invalid ${name}: "${shortText(text)}" (unknown group${unknown.length > 1 ? 's' : ''} ${named}; expected ${describe})`);
      }
      return new Set(words);
    },
  };
}

/** The `controls` value for a set of groups, as a link writes it. */
export function formatControls(visible, groups) {
  if (groups.every((g) => visible.has(g))) return 'all';
  const shown = groups.filter((g) => visible.has(g));
  return shown.length ? shown.join(' ') : 'none';
}

/**
 * Shows the control groups in `visible` and hides the others: every
 * element of `host` marked `data-controls="GROUP"` belongs to GROUP.
 */
export function applyControls(host, visible) {
  for (const node of host.querySelectorAll('[data-controls]')) node.hidden = !visible.has(node.dataset.controls);
}

// ---- reading and reporting --------------------------------------------------

/**
 * Reads a widget's attributes against its table and reports problems in
 * two boxes at the top of the widget: bad values (an alert, `console.error`)
 * and unknown attribute names (a notice, `console.warn`). Each problem is
 * logged once, when it appears.
 */
export class AttributeReader {
  constructor(host, spec) {
    this.host = host;
    this.spec = spec;
    this.last = {};
    this.errors = [];
    this.logged = new Set();
    for (const name of Object.keys(spec)) this.last[name] = this.parseDefault(name);
    // Names outside the table are not observed attributes: watch for them
    // coming and going (the widget hears about its own names itself).
    if ('MutationObserver' in window) {
      new MutationObserver((records) => {
        if (records.some((r) => !Object.hasOwn(spec, r.attributeName) && !isGlobal(r.attributeName))) this.report(this.errors, this.unknown());
      }).observe(host, { attributes: true });
    }
  }

  parseDefault(name) {
    const s = this.spec[name];
    return s.default === undefined ? undefined : parseBounded(s.type, s.default, name);
  }

  /**
   * Takes the model's bounds and defaults from the core's `constants()`
   * (once per page: every element of the tag shares the table) and reads
   * the attributes again, now checked against them.
   */
  resolve(constants) {
    for (const [name, s] of Object.entries(this.spec)) {
      if (!s.core) continue;
      if (!s.fromCore) {
        Object.assign(s, s.core(constants));
        s.fromCore = true;
      }
      // A value the looser type let through is not a last good value.
      this.last[name] = this.parseDefault(name);
    }
    return this.read();
  }

  /**
   * Attribute names of the host that neither the table nor HTML knows. The
   * table's own names only: `in` would also find `constructor`,
   * `toString` or `__proto__` on every object's prototype.
   */
  unknown() {
    return this.host.getAttributeNames().filter((n) => !Object.hasOwn(this.spec, n) && !isGlobal(n));
  }

  /**
   * Every attribute of the table → its value: the parsed attribute when it
   * is present and good, the last good value when it is bad, the default
   * when it is absent. Also refreshes the report boxes.
   */
  read() {
    const errors = [];
    for (const [name, s] of Object.entries(this.spec)) {
      const text = this.host.getAttribute(name);
      if (text === null) {
        this.last[name] = this.parseDefault(name);
        continue;
      }
      try {
        this.last[name] = parseBounded(s.type, text, name);
      } catch (e) {
        // Bounds the core has not given yet: reported once it has.
        if (!s.core || s.fromCore) errors.push(e.message);
      }
    }
    this.errors = errors;
    this.report(errors, this.unknown());
    return { ...this.last };
  }

  /** True while some attribute value is bad. */
  get hasErrors() {
    return Boolean(this.host.querySelector(':scope > .occgrid-attribute-error'));
  }

  report(errors, unknown) {
    const tag = this.host.localName;
    const known = Object.keys(this.spec).join(', ');
    const warnings = unknown.map((n) => {
      const v = this.host.getAttribute(n);
      return `unknown attribute ${shortText(n)}${v === '' ? '' : `="${shortText(v)}"`} (ignored; ${tag} knows: ${known})`;
    });
    const now = new Set([...errors, ...warnings]);
    for (const m of errors) if (!this.logged.has(m)) console.error(`${tag}: ${m}`);
    for (const m of warnings) if (!this.logged.has(m)) console.warn(`${tag}: ${m}`);
    this.logged = now;
    this.box('occgrid-error occgrid-attribute-error', 'alert', errors);
    this.box('occgrid-attribute-warning', 'status', warnings);
  }

  box(cls, role, lines) {
    const selector = `:scope > .${cls.split(' ').at(-1)}`;
    let box = this.host.querySelector(selector);
    if (!lines.length) {
      box?.remove();
      return;
    }
    if (!box) {
      box = el('div', { class: cls, role });
      // Errors above warnings, both above the widget's own content.
      const error = this.host.querySelector(':scope > .occgrid-attribute-error');
      if (role === 'status' && error) error.after(box);
      else this.host.prepend(box);
    }
    box.replaceChildren(...lines.map((m, i) => (i ? [el('br'), m] : [m])).flat());
  }
}

/**
 * The table as documentation rows: `[{ name, expected, default, doc }]`
 * (used by tests to check the README lists every attribute).
 */
export function describeAttributes(spec) {
  return Object.entries(spec).map(([name, s]) => ({ name, expected: s.type.describe, default: s.default, doc: s.doc }));
}

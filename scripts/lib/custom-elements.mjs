// The Custom Elements Manifest (custom-elements.json, schema 2.1) of the
// widgets, for instructors' editors: each element's tag, class, summary and
// attributes. Nothing in it is written by hand: every widget module declares
// its attributes once, as its class's `static attributeSpec` (name → { type,
// default, doc }, widgets/lib/attributes.js), the table the widget itself
// checks its attributes against; this module imports the widget modules and
// reads those tables, with the bounds and defaults the core gives
// (`core: (constants) => …`) resolved against the core's `constants()`, as
// the widget does once its core has loaded. So the manifest cannot say
// something the widgets do not (tests/browser/dist.test.mjs compares them).
//
// The widget modules are browser modules: they are imported in a child
// process (this file run as a script) with the few DOM globals their
// top level touches stubbed, so the build's own process never sees them.
//
// Usage: `customElementsManifest(dir, { glue, wasm })` with `dir` a bundle
// being written by scripts/dist.mjs (widgets/, pkg/, vendor/ in place) and
// `glue`, `wasm` its core's files (paths relative to `dir`): the manifest as
// an object, module paths relative to `dir`.
import fs from 'node:fs';
import path from 'node:path';
import { spawnSync } from 'node:child_process';
import { fileURLToPath, pathToFileURL } from 'node:url';

const SCHEMA_VERSION = '2.1.0';
const self = fileURLToPath(import.meta.url);

/** The manifest of the widgets in bundle `dir` (see the file's comment). */
export function customElementsManifest(dir, { glue, wasm }) {
  const run = spawnSync(process.execPath, [self, dir, glue, wasm], { encoding: 'utf8', maxBuffer: 16 << 20 });
  if (run.status !== 0) {
    throw new Error(`reading the widgets' attribute declarations failed:\n${run.stderr || run.stdout}`);
  }
  return JSON.parse(run.stdout);
}

/**
 * An attribute as the manifest states it. `type` is the attribute's own
 * text type; what it must hold is the declaration's `describe`, the words
 * the widget's own error message uses ("expected …").
 */
export function manifestAttribute(name, spec) {
  const out = {
    name,
    description: `${spec.doc}. Expected: ${spec.type.describe}.`,
    type: { text: 'string' },
  };
  // A default is a JavaScript expression in the schema: the attribute's text, quoted.
  if (spec.default !== undefined) out.default = JSON.stringify(spec.default);
  return out;
}

/** A declaration with the core's bounds and defaults applied, as the widget applies them. */
export function resolvedSpec(spec, constants) {
  return Object.fromEntries(Object.entries(spec).map(([name, s]) => [name, s.core ? { ...s, ...s.core(constants) } : s]));
}

/** A module's opening comment, up to its first blank comment line, as one paragraph. */
function summary(text) {
  const lines = [];
  for (const line of text.split('\n')) {
    const m = /^\/\/ ?(.*)$/.exec(line);
    if (!m || m[1].trim() === '') break;
    lines.push(m[1].trim());
  }
  return lines.join(' ');
}

/** Stubs the DOM globals the widget modules touch when they load (not when they run). */
function stubDom() {
  const node = () => ({
    style: {}, dataset: {}, classList: { add() {}, remove() {}, toggle() {} },
    setAttribute() {}, append() {}, prepend() {}, addEventListener() {},
  });
  const registry = new Map();
  globalThis.HTMLElement ??= class HTMLElement {};
  globalThis.customElements ??= {
    define(tag, cls) {
      if (registry.has(tag)) throw new Error(`${tag} defined twice`);
      registry.set(tag, cls);
    },
    get: (tag) => registry.get(tag),
  };
  globalThis.document ??= {
    querySelector: () => null,
    querySelectorAll: () => [],
    getElementsByTagName: () => [],
    createElement: node,
    head: node(),
    body: node(),
    addEventListener() {},
  };
  return registry;
}

/** Run as a script: prints the manifest of bundle `dir`, whose core is `glue` and `wasm`. */
async function main(dir, glue, wasm) {
  const registry = stubDom();
  const core = await import(pathToFileURL(path.join(dir, glue)).href);
  core.initSync({ module: fs.readFileSync(path.join(dir, wasm)) });
  const constants = core.constants();

  const modules = [];
  const files = fs.readdirSync(path.join(dir, 'widgets')).filter((f) => f.endsWith('.js')).sort();
  for (const file of files) {
    const before = new Set(registry.keys());
    const full = path.join(dir, 'widgets', file);
    await import(pathToFileURL(full).href);
    const tags = [...registry.keys()].filter((t) => !before.has(t));
    if (!tags.length) continue;
    const modulePath = `widgets/${file}`;
    const description = summary(fs.readFileSync(full, 'utf8'));
    const declarations = tags.map((tagName) => {
      const cls = registry.get(tagName);
      if (!cls.attributeSpec) throw new Error(`${modulePath}: <${tagName}> declares no attributeSpec`);
      const spec = resolvedSpec(cls.attributeSpec, constants);
      return {
        kind: 'class',
        description,
        name: cls.name,
        tagName,
        customElement: true,
        superclass: { name: 'HTMLElement' },
        attributes: Object.entries(spec).map(([name, s]) => manifestAttribute(name, s)),
      };
    });
    modules.push({
      kind: 'javascript-module',
      path: modulePath,
      declarations,
      exports: declarations.map((d) => ({
        kind: 'custom-element-definition',
        name: d.tagName,
        declaration: { name: d.name, module: modulePath },
      })),
    });
  }
  fs.writeSync(1, JSON.stringify({ schemaVersion: SCHEMA_VERSION, modules }));
  // A widget module may hold the event loop open (a MessageChannel port).
  process.exit(0);
}

if (process.argv[1] && path.resolve(process.argv[1]) === self) {
  main(path.resolve(process.argv[2]), process.argv[3], process.argv[4]).catch((e) => {
    process.stderr.write(`${e && e.stack ? e.stack : e}\n`);
    process.exit(1);
  });
}

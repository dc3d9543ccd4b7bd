// Keeps the wasm core's shadow stack whole when a call into it throws.
//
// Rust code compiled to wasm keeps its stack frames in linear memory below a
// mutable global, `__stack_pointer`, that each function lowers on entry and
// raises on return. When an export throws instead (the glue's "null pointer
// passed to rust" for a call on a freed instance, "recursive use of an
// object", any message the core throws), the exception unwinds past the code
// that would raise it again: every such call leaks its frame, and after a few
// thousand the stack has grown down into the data below it and every later
// call fails with "memory access out of bounds". wasm-bindgen fixed this in
// a release later than the one Cargo.toml pins, by saving the stack pointer
// on entry to each export and restoring it before the exception leaves; this
// step does the same for one module built by scripts/build.sh:
//
//   node scripts/lib/guard-stack-pointer.mjs OUT/NAME_bg.wasm OUT/NAME.js
//
// 1. It finds the stack pointer by its name in the wasm's `name` section (so
//    it runs before strip-wasm-names.mjs) and exports it as
//    `__occgrid_stack_pointer`.
// 2. It makes the glue keep, in place of the instance's exports, an object
//    of the same members in which every function is wrapped: it saves the
//    stack pointer, calls, and on a throw restores it and rethrows. Memory,
//    tables and globals pass through.
// 3. It makes each method and getter of the glue's classes refuse a freed
//    instance in JavaScript, with an Error that names the class, before the
//    core's own check ("null pointer passed to rust") would say it less
//    clearly.
//
// Whatever it cannot identify for certain (no name for the stack pointer, a
// glue whose text is not the one it patches) stops the build: a module that
// ships unguarded is not an option.
import fs from 'node:fs';
import { leb } from './wasm-leb.mjs';

export const STACK_POINTER = '__stack_pointer';
export const EXPORT_NAME = '__occgrid_stack_pointer';

const SECTION = { custom: 0, import: 2, global: 6, export: 7 };
const NAME_SUBSECTION_GLOBALS = 7;
const EXTERNAL_GLOBAL = 3;
const I32 = 0x7f;
const MUTABLE = 1;

function refuse(file, why) {
  throw new Error(`${file}: ${why}; the stack pointer cannot be guarded (scripts/lib/guard-stack-pointer.mjs), so the build stops`);
}

function encodeLeb(value) {
  const out = [];
  do {
    let b = value % 128;
    value = Math.floor(value / 128);
    if (value > 0) b |= 0x80;
    out.push(b);
  } while (value > 0);
  return Buffer.from(out);
}

function readName(bytes, i) {
  const [len, at] = leb(bytes, i);
  return [Buffer.from(bytes.subarray(at, at + len)).toString(), at + len];
}

function encodeName(name) {
  const text = Buffer.from(name);
  return Buffer.concat([encodeLeb(text.length), text]);
}

/** The module's sections in order: `{ id, start, body, end, name? }`. */
function sections(bytes) {
  const list = [];
  let i = 8;
  while (i < bytes.length) {
    const start = i;
    const id = bytes[i++];
    const [size, body] = leb(bytes, i);
    const section = { id, start, body, end: body + size };
    if (id === SECTION.custom) [section.name, section.body] = readName(bytes, body);
    list.push(section);
    i = section.end;
  }
  return list;
}

/** The index of the global the `name` section calls `wanted`, or undefined. */
function globalNamed(bytes, nameSection, wanted) {
  let i = nameSection.body;
  while (i < nameSection.end) {
    const id = bytes[i++];
    const [size, body] = leb(bytes, i);
    if (id === NAME_SUBSECTION_GLOBALS) {
      let [count, j] = leb(bytes, body);
      for (let n = 0; n < count; n++) {
        let index, name;
        [index, j] = leb(bytes, j);
        [name, j] = readName(bytes, j);
        if (name === wanted) return index;
      }
    }
    i = body + size;
  }
  return undefined;
}

/** How many globals the module imports (they come first in the global index space). */
function importedGlobals(bytes, importSection) {
  if (!importSection) return 0;
  let [count, i] = leb(bytes, importSection.body);
  let globals = 0;
  const skipLimits = (j) => {
    const flags = bytes[j++];
    [, j] = leb(bytes, j);
    if (flags & 1) [, j] = leb(bytes, j);
    return j;
  };
  for (let n = 0; n < count; n++) {
    [, i] = readName(bytes, i);
    [, i] = readName(bytes, i);
    const kind = bytes[i++];
    if (kind === 0) [, i] = leb(bytes, i); // a function: its type
    else if (kind === 1) i = skipLimits(i + 1); // a table: its element type, limits
    else if (kind === 2) i = skipLimits(i); // a memory: limits
    else if (kind === EXTERNAL_GLOBAL) { globals += 1; i += 2; } // value type, mutability
    else if (kind === 4) [, i] = leb(bytes, i + 1); // a tag: attribute, type
    else throw new Error(`an import of unknown kind ${kind}`);
  }
  return globals;
}

/** The value type and mutability of the module's own global `index` (its first entries' initialisers are skipped). */
function globalType(bytes, globalSection, index) {
  let [count, i] = leb(bytes, globalSection.body);
  if (index >= count) return undefined;
  for (let n = 0; ; n++) {
    const type = { value: bytes[i], mutable: bytes[i + 1] };
    if (n === index) return type;
    i += 2;
    // A constant expression: one instruction, then `end`.
    const op = bytes[i++];
    if (op === 0x41 || op === 0x42 || op === 0x23 || op === 0xd2) [, i] = leb(bytes, i);
    else if (op === 0x43) i += 4;
    else if (op === 0x44) i += 8;
    else if (op === 0xd0) i += 1;
    else return undefined;
    if (bytes[i++] !== 0x0b) return undefined;
  }
}

/** The wasm module `bytes` with its stack pointer exported as EXPORT_NAME. */
export function exportStackPointer(bytes, file = 'the module') {
  const list = sections(bytes);
  const names = list.find((s) => s.id === SECTION.custom && s.name === 'name');
  if (!names) refuse(file, 'it has no `name` section (run this step before strip-wasm-names.mjs)');
  const index = globalNamed(bytes, names, STACK_POINTER);
  if (index === undefined) refuse(file, `its \`name\` section names no global \`${STACK_POINTER}\``);
  const imported = importedGlobals(bytes, list.find((s) => s.id === SECTION.import));
  const globals = list.find((s) => s.id === SECTION.global);
  const type = index >= imported && globals ? globalType(bytes, globals, index - imported) : undefined;
  if (!type || type.value !== I32 || type.mutable !== MUTABLE) {
    refuse(file, `global ${index}, \`${STACK_POINTER}\`, is not a mutable i32 of the module's own`);
  }
  const exportSection = list.find((s) => s.id === SECTION.export);
  if (!exportSection) refuse(file, 'it has no export section');
  let [count, i] = leb(bytes, exportSection.body);
  for (let n = 0; n < count; n++) {
    let name;
    [name, i] = readName(bytes, i);
    if (name === EXPORT_NAME) refuse(file, `it already exports \`${EXPORT_NAME}\` (built twice?)`);
    [, i] = leb(bytes, i + 1);
  }
  const body = Buffer.concat([
    encodeLeb(count + 1),
    bytes.subarray(leb(bytes, exportSection.body)[1], exportSection.end),
    encodeName(EXPORT_NAME), Buffer.from([EXTERNAL_GLOBAL]), encodeLeb(index),
  ]);
  return Buffer.concat([
    bytes.subarray(0, exportSection.start),
    Buffer.from([SECTION.export]), encodeLeb(body.length), body,
    bytes.subarray(exportSection.end),
  ]);
}

/** What the glue does on instantiation, as wasm-bindgen writes it; both the sync and the async path go through it. */
const FINALIZE = 'function __wbg_finalize_init(instance, module) {\n    wasmInstance = instance;\n    wasm = instance.exports;\n';
const FINALIZE_GUARDED = FINALIZE.replace('wasm = instance.exports;', 'wasm = guardedExports(instance.exports);');

/** Appended to the glue: the wrapper every export is called through. */
const GUARD = `
// Every function of the wasm exports, wrapped so that an exception leaving
// it restores the shadow stack pointer it lowered (the wasm code that would
// raise it again is skipped by the throw): added by
// scripts/lib/guard-stack-pointer.mjs, which says why.
function guardedExports(exports) {
    const stackPointer = exports.${EXPORT_NAME};
    if (!(stackPointer instanceof WebAssembly.Global)) throw new Error('the wasm core exports no stack pointer: rebuild it with scripts/build.sh');
    const guarded = Object.create(null);
    for (const [name, value] of Object.entries(exports)) {
        guarded[name] = typeof value === 'function' ? guardedCall(value, stackPointer) : value;
    }
    return Object.freeze(guarded);
}

function guardedCall(f, stackPointer) {
    return function (...args) {
        const saved = stackPointer.value;
        try {
            return f(...args);
        } catch (e) {
            stackPointer.value = saved;
            throw e;
        }
    };
}
`;

/** Appended to the glue: the refusal of a call on a freed instance. */
const FREED = `
function freedInstance(className) {
    throw new Error(\`\${className} was freed (free() was called on it) and can no longer be used\`);
}
`;

/** A method's or getter's call into the core with the instance's handle, as the glue writes it. */
const HANDLE_CALL = /\bwasm\.\w+\(this\.__wbg_ptr\b/g;
const CLASS_HEADER = /^export class (\w+) \{$/gm;

/**
 * The glue `text` with every call into the core on `this.__wbg_ptr` made to
 * refuse a freed instance (a handle of 0) by its class's name.
 */
function refuseFreedInstances(text, file) {
  const headers = [...text.matchAll(CLASS_HEADER)];
  let patched = 0;
  const out = text.replace(HANDLE_CALL, (call, at) => {
    const header = headers.findLast((h) => h.index < at);
    if (!header || text.slice(header.index, at).includes('\n}\n')) {
      refuse(file, `a call on \`this.__wbg_ptr\` outside a class body, at character ${at}`);
    }
    patched += 1;
    return `${call} || freedInstance('${header[1]}')`;
  });
  if (headers.length === 0 || patched < headers.length) {
    refuse(file, `found ${headers.length} classes and ${patched} calls on \`this.__wbg_ptr\`: not the glue this step patches`);
  }
  return out;
}

/** The glue `text` with its exports guarded. */
export function guardGlue(text, file = 'the glue') {
  const count = (needle) => text.split(needle).length - 1;
  if (count('instance.exports') !== 1 || count(FINALIZE) !== 1) {
    refuse(file, 'its text is not the wasm-bindgen glue this step patches (one `wasm = instance.exports;` in `__wbg_finalize_init`)');
  }
  for (const name of ['guardedExports', 'guardedCall', 'freedInstance']) {
    if (count(`function ${name}`)) refuse(file, `it already defines \`${name}\` (built twice?)`);
  }
  return refuseFreedInstances(text.replace(FINALIZE, FINALIZE_GUARDED), file) + GUARD + FREED;
}

const [wasmFile, glueFile] = process.argv.slice(2);
if (wasmFile && glueFile) {
  const bytes = exportStackPointer(fs.readFileSync(wasmFile), wasmFile);
  await WebAssembly.compile(bytes); // refuse to write a module that does not validate
  const glue = guardGlue(fs.readFileSync(glueFile, 'utf8'), glueFile);
  fs.writeFileSync(wasmFile, bytes);
  fs.writeFileSync(glueFile, glue);
} else if (wasmFile || glueFile) {
  throw new Error('usage: node scripts/lib/guard-stack-pointer.mjs OUT/NAME_bg.wasm OUT/NAME.js');
}

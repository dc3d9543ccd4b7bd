// Every export of the wasm core the page ships (both of its modules,
// pkg/occgrid.js and pkg/occgrid_logs.js), called
// with hostile values: revoked Proxies, Proxies and getters that throw,
// objects whose valueOf / toString / Symbol.toPrimitive / toJSON free the
// instance being called, NaN, the infinities, huge and negative numbers,
// wrong types, a string of ten million characters, deep, wide and cyclic
// objects. The exports are found by reflection (every class, its
// constructor, static methods, methods and getters, and every free
// function), so a new method is fuzzed without editing this file. First a
// sweep puts each hostile value in each parameter of each callable, then a
// fixed-seed run makes random calls. Every call must return, or throw an
// `Error` of the core's own with a message: a TypeError from the glue, a
// `WebAssembly.RuntimeError` (`unreachable`, "memory access out of
// bounds"), or an instance left borrowed ("recursive use of an object")
// fails. After every call the instance still answers, and at the end every
// instance and a fresh one of each class do, and no hostile hook was ever
// asked for a value. Then calls that throw by the hundred thousand (on freed
// instances, through the glue and straight into the core, and on an
// instance its own call holds borrowed) and a large typed array in every
// parameter must leave the core computing the chapter's numbers as before,
// its stack pointer where it was. Needs pkg/ (npm run build).
import test from 'node:test';
import assert from 'node:assert/strict';
import { loadCore } from '../../scripts/lib/load-core.mjs';

// One namespace of the two modules' exports (each class keeps its own module's memory).
const modules = [await loadCore(), await loadCore({ logs: true })];
const core = Object.assign({}, ...modules.map((m) => m.core));
/** The module (`{ core, memory }`) that exports `name`. */
const moduleOf = (name) => modules.find((m) => Object.hasOwn(m.core, name));

/** The random calls after the sweep; with the sweep, a few seconds in all. */
const RANDOM_CALLS = 2000;
const SEED = 20240917;

/** mulberry32: a small seeded generator, so that a failure replays. */
function generator(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

/** A tiny valid CARMEN log, for the sessions that are built from bytes. */
const LOG = new TextEncoder().encode('FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n'.repeat(5));

/**
 * How to build a cheap instance of a class that needs arguments (a class
 * not listed is built with none; if that fails, the test says to add it).
 */
const RECIPES = {
  MapWeaver: () => new core.MapWeaver({ laps: 1, training: { triplets: 400, epochs: 1 } }),
  RealLogSession: () => {
    const s = new core.RealLogSession(LOG, 'fuzz.log');
    s.read(2);
    return s;
  },
  SensorFusion: () => new core.SensorFusion({ step: 0.4 }, undefined),
  DoorwayTrap: () => new core.DoorwayTrap(undefined),
  InverseWorkbench: () => new core.InverseWorkbench(undefined),
};

/** How to ask an instance of a class without getters that it still answers. */
const ANSWERS = {
  InverseWorkbench: (x) => x.readout(),
  RealLogSession: (x) => x.state(),
};

/** Exports that are the module's loader, not the core. */
const LOADER = new Set(['default', 'initSync']);

const isClass = (f) => typeof f === 'function' && /^class\b/.test(Function.prototype.toString.call(f));
/** Own callable members of `object` worth calling: no internals (`__wrap`, `__destroy_into_raw`), no `free`. */
function members(object) {
  return Object.getOwnPropertyNames(object).filter((name) => {
    if (name.startsWith('__') || ['constructor', 'free', 'length', 'name', 'prototype'].includes(name)) return false;
    const d = Object.getOwnPropertyDescriptor(object, name);
    return typeof d.value === 'function';
  });
}
const getters = (C) => Object.getOwnPropertyNames(C.prototype).filter((n) => Object.getOwnPropertyDescriptor(C.prototype, n).get);

const classes = Object.entries(core).filter(([name, f]) => !LOADER.has(name) && isClass(f));
const functions = Object.entries(core).filter(([name, f]) => !LOADER.has(name) && typeof f === 'function' && !isClass(f));

/** Counts every time JavaScript asked a hostile object for a value (it never may). */
const coerced = { count: 0, by: [] };

/** A Proxy that has been revoked: every question put to it throws. */
function revoked() {
  const { proxy, revoke } = Proxy.revocable({}, {});
  revoke();
  return proxy;
}

/**
 * The hostile values, by name. `victim()` is the instance a freeing hook
 * frees: the instance being called, or a bystander for free functions.
 */
function hostileValues(victim) {
  const asked = (how) => () => {
    coerced.count += 1;
    coerced.by.push(how);
    try {
      victim().free();
    } catch {
      // Already freed, or borrowed by the call: still a value.
    }
  };
  const valueOf = asked('valueOf');
  const toString = asked('toString');
  const toPrimitive = asked('Symbol.toPrimitive');
  const toJSON = asked('toJSON');
  const deep = {};
  let node = deep;
  for (let i = 0; i < 5000; i++) node = node.next = {};
  const cyclic = { a: 1 };
  cyclic.self = cyclic;
  const wide = {};
  for (let i = 0; i <= 100_000; i++) wide[`k${i}`] = i;
  const throwingGetter = Object.defineProperty({}, 'clamp', { enumerable: true, get() { throw new Error('a getter threw'); } });
  const throwingTraps = new Proxy({}, {
    ownKeys() { return ['seed', 'clamp']; },
    getOwnPropertyDescriptor() { return { value: 1, enumerable: true, configurable: true }; },
    get() { throw new Error('a get trap threw'); },
  });
  const noKeys = new Proxy([], { ownKeys() { throw new Error('an ownKeys trap threw'); } });
  const lyingBytes = new Uint8Array([1, 0, 1]);
  Object.defineProperty(lyingBytes, 'length', { get() { throw new Error('a length getter threw'); } });
  const lookAlikeBytes = Object.setPrototypeOf({ length: 1e9 }, Uint8Array.prototype);
  const freeingNumber = Object.assign(new Number(1), { valueOf() { valueOf(); return 1; } });
  return [
    ['NaN', NaN], ['Infinity', Infinity], ['-Infinity', -Infinity], ['1e308', 1e308], ['-1e308', -1e308],
    ['2^53', 2 ** 53], ['2^64', 2 ** 64], ['-1', -1], ['-0', -0], ['0', 0], ['0.5', 0.5], ['1', 1], ['7', 7], ['1e9', 1e9],
    ['""', ''], ['"x"', 'x'], ['"1"', '1'], ['"0x10"', '0x10'], ['ten million characters', 'x'.repeat(1e7)],
    ['true', true], ['false', false], ['null', null], ['undefined', undefined], ['10n', 10n], ['a symbol', Symbol('s')],
    ['a function', () => 1], ['[]', []], ['[1, 0, 1]', [1, 0, 1]], ['{}', {}], ['nested 5000 deep', deep], ['cyclic', cyclic],
    ['100,001 keys', wide], ['an array of a million', new Array(1e6).fill(0)],
    ['a revoked Proxy', revoked()], ['{ resolution: a revoked Proxy }', { resolution: revoked(), clamp: revoked() }],
    ['[a revoked Proxy]', [revoked()]], ['a revoked function Proxy', (() => { const r = Proxy.revocable(() => 1, {}); r.revoke(); return r.proxy; })()],
    ['a throwing getter', throwingGetter], ['throwing traps', throwingTraps], ['a throwing ownKeys trap', noKeys],
    ['a valueOf that frees', { valueOf() { valueOf(); return 1; } }],
    ['a toString that frees', { toString() { toString(); return '1'; } }],
    ['a Symbol.toPrimitive that frees', { [Symbol.toPrimitive]() { toPrimitive(); return 1; } }],
    ['a toJSON that frees', { toJSON() { toJSON(); return 1; } }],
    ['a Number whose valueOf frees', freeingNumber],
    ['{ clamp: a valueOf that frees }', { clamp: { valueOf() { valueOf(); return 1; } } }],
    ['a Uint8Array whose length throws', lyingBytes], ['a Uint8Array look-alike', lookAlikeBytes],
    ['a Proxy of a Uint8Array', new Proxy(new Uint8Array(LOG), {})], ['a detached ArrayBuffer', (() => { const b = new ArrayBuffer(8); structuredClone(b, { transfer: [b] }); return b; })()],
    ['a log', LOG], ['{ "__proto__": ... }', JSON.parse('{"__proto__": {"clamp": 1}}')],
  ];
}

/** A value as a failure message names it. */
function named(value, table) {
  const hit = table.find(([, v]) => Object.is(v, value));
  if (hit) return hit[0];
  try {
    return JSON.stringify(value) ?? String(value);
  } catch {
    return typeof value;
  }
}

/**
 * Calls `f` and judges the outcome: a result (an instance it returns is
 * freed) or an Error of the core's own, with a message.
 */
function judge(label, f) {
  let result;
  try {
    result = f();
  } catch (e) {
    assert.ok(e instanceof Error, `${label} threw a non-Error: ${String(e)}`);
    assert.ok(!(e instanceof WebAssembly.RuntimeError), `${label} stopped the core: ${e.message}`);
    assert.equal(Object.getPrototypeOf(e), Error.prototype, `${label} threw a ${e.constructor.name} from outside the core: ${e.message}`);
    assert.ok(e.message.length > 0, `${label} threw an Error without a message`);
    assert.doesNotMatch(e.message, /unreachable|memory access|recursive use|borrowed|null pointer/, label);
    return;
  }
  if (result && typeof result === 'object' && Object.hasOwn(result, '__wbg_ptr')) result.free();
}

/** Asserts that `x`, an instance of class `name`, still answers. */
function answers(name, x, after) {
  assert.ok(x.__wbg_ptr !== 0, `the ${name} was freed by ${after}`);
  const C = core[name];
  const own = getters(C);
  assert.ok(own.length || ANSWERS[name], `no way to ask a ${name} whether it answers: add it to ANSWERS`);
  try {
    for (const g of own) void x[g];
    ANSWERS[name]?.(x);
  } catch (e) {
    assert.fail(`the ${name} no longer answers after ${after}: ${e.message}`);
  }
}

function build(name) {
  const make = RECIPES[name] ?? (() => new core[name]());
  try {
    return make();
  } catch (e) {
    assert.fail(`cannot build a ${name} to fuzz (${e.message}): add a recipe to RECIPES`);
  }
}

/**
 * Every callable of the core: `{ label, arity, call(args), instance? }`,
 * methods called on `instances[name]`.
 */
function callablesOf(instances) {
  const callables = [];
  for (const [name, C] of classes) {
    callables.push({ label: `new ${name}`, arity: C.length, call: (args) => new C(...args) });
    for (const m of members(C)) callables.push({ label: `${name}.${m}`, arity: C[m].length, call: (args) => C[m](...args) });
    for (const m of members(C.prototype)) {
      callables.push({ label: `${name}#${m}`, arity: C.prototype[m].length, instance: name, call: (args) => instances[name][m](...args) });
    }
  }
  for (const [name, f] of functions) callables.push({ label: name, arity: f.length, call: (args) => f(...args) });
  return callables;
}

test('every export of the core takes hostile values with an Error, and every instance keeps answering', () => {
  assert.ok(classes.length >= 5 && functions.length >= 8, `found ${classes.length} classes and ${functions.length} functions`);
  const instances = Object.fromEntries(classes.map(([name]) => [name, build(name)]));
  // The bystander a freeing hook frees when no instance is being called.
  const bystander = build('DoorwayTrap');
  let current = () => bystander;
  const table = hostileValues(() => current());
  const pool = table.map(([, v]) => v);
  // The random run leaves out the values slow to refuse (the 100,001 keys
  // are listed on every reading): the sweep gives each to every parameter.
  const randomPool = table.filter(([name]) => name !== '100,001 keys').map(([, v]) => v);

  const callables = callablesOf(instances);

  const run = (c, args) => {
    current = c.instance ? () => instances[c.instance] : () => bystander;
    const label = `${c.label}(${args.map((a) => named(a, table)).join(', ')})`;
    judge(label, () => c.call(args));
    if (c.instance) answers(c.instance, instances[c.instance], label);
    answers('DoorwayTrap', bystander, label);
  };

  // The sweep: each hostile value in each parameter, 0 in the others (a
  // callable without parameters gets a few as an extra argument).
  const extras = [revoked(), table.find(([n]) => n === 'a valueOf that frees')[1], undefined];
  let calls = 0;
  for (const c of callables) {
    const arity = Math.max(1, c.arity);
    for (let p = 0; p < arity; p++) {
      for (const v of c.arity ? pool : extras) {
        const args = new Array(arity).fill(0);
        args[p] = v;
        run(c, args);
        calls += 1;
      }
    }
  }
  // The random run: any values, in any parameters, with one extra now and then.
  const random = generator(SEED);
  const pick = (list) => list[Math.floor(random() * list.length)];
  for (let i = 0; i < RANDOM_CALLS; i++) {
    const c = pick(callables);
    const n = c.arity + (random() < 0.1 ? 1 : 0);
    run(c, Array.from({ length: n }, () => pick(randomPool)));
    calls += 1;
  }

  assert.equal(coerced.count, 0, `the core asked hostile objects for a value: ${coerced.by.slice(0, 5).join(', ')}`);
  for (const [name, x] of Object.entries(instances)) {
    answers(name, x, `${calls} calls`);
    x.free();
    const fresh = build(name);
    answers(name, fresh, 'the fuzzing, as a fresh instance');
    fresh.free();
  }
  answers('DoorwayTrap', bystander, `${calls} calls`);
  bystander.free();
});

/**
 * Calls per method and getter of a freed instance, each of which throws.
 * The core keeps its stack frames on a shadow stack in wasm memory (1 MiB)
 * whose pointer an exception thrown inside the core skips restoring;
 * before scripts/build.sh guarded it, each such call leaked its frame and
 * 4,672 to 32,768 calls on one module stopped every later call with
 * "memory access out of bounds".
 */
const FREED_CALLS = 20_000;
/**
 * Calls per method straight into the core with a freed handle, where the
 * glue's own check no longer sends them (each three times dearer): their
 * sum on one module is still more than 30 times what once broke it.
 */
const FREED_CORE_CALLS = 5_000;
/**
 * Calls that meet their own instance borrowed ("recursive use of an
 * object"), per class that can be made to: refused from inside wasm, inside
 * a call of the instance's own that is still running.
 */
const BORROWED_CALLS = 20_000;
/**
 * The length of the typed arrays given in each parameter of each callable:
 * large beside any value a parameter takes, while the 130-odd calls stay
 * near a second (a refusal describes the value it refuses).
 */
const LARGE_ARRAY_LENGTH = 5_000_000;

/** The name of the core's export a glue method or getter calls with the instance's handle. */
function coreExportOf(C, member) {
  const d = Object.getOwnPropertyDescriptor(C.prototype, member);
  const source = Function.prototype.toString.call(d.value ?? d.get);
  const found = source.match(/\bwasm\.(\w+)\(this\.__wbg_ptr\b/);
  assert.ok(found, `cannot find the core's export behind ${C.name}#${member}`);
  return found[1];
}

/** What must come out the same after the calls that throw: the chapter's numbers and a log's reading. */
function chapterNumbers() {
  const session = new core.RealLogSession(LOG, 'fuzz.log');
  session.read(5);
  const numbers = { workedExample: core.workedExample(), constants: core.constants(), session: session.state() };
  session.free();
  return numbers;
}

/** Runs `f` with errors built without a stack trace: the phases throw hundreds of thousands. */
function withoutStackTraces(f) {
  const limit = Error.stackTraceLimit;
  Error.stackTraceLimit = 0;
  try {
    return f();
  } finally {
    Error.stackTraceLimit = limit;
  }
}

/** Calls `f` `times` times; each must throw an Error that is not the core stopping. Returns the first message. */
function throwsEveryTime(label, times, f) {
  let first;
  for (let i = 0; i < times; i++) {
    try {
      f();
    } catch (e) {
      if (!(e instanceof Error) || e instanceof WebAssembly.RuntimeError) assert.fail(`${label}, call ${i + 1}: ${e?.constructor?.name}: ${e?.message}`);
      first ??= e.message;
      continue;
    }
    assert.fail(`${label}, call ${i + 1}, returned`);
  }
  return first;
}

/** The core's stack pointer of each module, which build.sh exports (undefined if it does not). */
const stackPointers = () => modules.map((m) => m.core.initSync().__occgrid_stack_pointer?.value);

/** Asserts that the core computes as it did, that every class builds afresh and answers, and that no stack was lost. */
function coreIntact(numbers, pointers, after) {
  let now;
  try {
    now = chapterNumbers();
  } catch (e) {
    assert.fail(`the core no longer computes after ${after}: ${e.message}`);
  }
  assert.deepEqual(now, numbers, `the chapter's numbers after ${after}`);
  for (const [name] of classes) {
    const fresh = build(name);
    answers(name, fresh, `${after}, as a fresh instance`);
    fresh.free();
  }
  for (const [i, m] of modules.entries()) {
    assert.ok(m.core.initSync().__occgrid_stack_pointer instanceof WebAssembly.Global, 'the module exports its stack pointer (scripts/build.sh)');
    assert.equal(stackPointers()[i], pointers[i], `the stack pointer after ${after}`);
  }
}

test('calls on a freed instance, tens of thousands per method, each refuse and leave the core whole', () => {
  const numbers = chapterNumbers();
  const pointers = stackPointers();
  let calls = 0;
  const messages = [];
  const started = performance.now();
  withoutStackTraces(() => {
    for (const [name, C] of classes) {
      const x = build(name);
      x.free();
      const raw = moduleOf(name).core.initSync();
      for (const m of [...members(C.prototype), ...getters(C)]) {
        const isGetter = !members(C.prototype).includes(m);
        const zeros = isGetter ? [] : new Array(C.prototype[m].length).fill(0);
        // Through the glue, as a page would call it.
        const message = throwsEveryTime(`${name}#${m} on a freed instance`, FREED_CALLS, isGetter ? () => x[m] : () => x[m](...zeros));
        messages.push([`${name}#${m}`, message]);
        // Straight into the core with the handle of a freed instance: the
        // core throws from inside wasm.
        const exported = raw[coreExportOf(C, m)];
        const args = new Array(exported.length).fill(0);
        throwsEveryTime(`the core's ${coreExportOf(C, m)} with a freed handle`, FREED_CORE_CALLS, () => exported(...args));
        calls += FREED_CALLS + FREED_CORE_CALLS;
      }
      // free() again: the core refuses the freed handle.
      throwsEveryTime(`${name}#free a second time`, FREED_CORE_CALLS, () => x.free());
      calls += FREED_CORE_CALLS;
    }
  });
  const ms = performance.now() - started;
  coreIntact(numbers, pointers, `${calls} calls on freed instances (${Math.round(ms)} ms)`);
  for (const [label, message] of messages) {
    assert.match(message, new RegExp(`^${label.split('#')[0]} was freed `), `${label} on a freed instance says so`);
  }
});

test('calls that meet their own instance borrowed refuse and leave the core whole', () => {
  const numbers = chapterNumbers();
  const pointers = stackPointers();
  let borrowed = 0;
  const started = performance.now();
  withoutStackTraces(() => {
    for (const [name, C] of classes) {
      const x = build(name);
      const own = getters(C);
      // Asks the instance while one of its own methods holds it: a getter
      // or a method of ANSWERS, which the core refuses from inside wasm.
      const reenter = () => {
        try {
          if (own.length) void x[own[0]];
          else ANSWERS[name](x);
        } catch (e) {
          assert.ok(!(e instanceof WebAssembly.RuntimeError), `${name}: ${e.message}`);
          if (/recursive use/.test(e.message)) borrowed += 1;
        }
      };
      const trap = () => { reenter(); return undefined; };
      const meddler = new Proxy({}, {
        get: trap, has: trap,
        ownKeys() { reenter(); return []; },
        getOwnPropertyDescriptor: trap,
      });
      // The first method and parameter in which the meddler meets the instance borrowed.
      let found;
      for (const m of members(C.prototype)) {
        for (let p = 0; p < C.prototype[m].length && !found; p++) {
          const args = new Array(C.prototype[m].length).fill(0);
          args[p] = meddler;
          const before = borrowed;
          judge(`${name}#${m} with a meddler`, () => x[m](...args));
          if (borrowed > before) found = () => x[m](...args);
        }
        if (found) break;
      }
      if (!found) continue;
      for (let i = 0; i < BORROWED_CALLS; i++) {
        try {
          found();
        } catch (e) {
          assert.ok(!(e instanceof WebAssembly.RuntimeError), `${name}, call ${i + 1} with a meddler: ${e.message}`);
        }
      }
      answers(name, x, `${BORROWED_CALLS} calls with a meddler`);
      x.free();
    }
  });
  assert.ok(borrowed >= 2 * BORROWED_CALLS, `only ${borrowed} calls met a borrowed instance`);
  coreIntact(numbers, pointers, `${borrowed} calls on a borrowed instance (${Math.round(performance.now() - started)} ms)`);
});

test('a large typed array in every parameter of every callable is refused or taken, and the core stays whole', () => {
  const numbers = chapterNumbers();
  const pointers = stackPointers();
  const instances = Object.fromEntries(classes.map(([name]) => [name, build(name)]));
  const arrays = [Uint8Array, Float64Array, Int32Array].map((T) => new T(LARGE_ARRAY_LENGTH));
  let calls = 0;
  const started = performance.now();
  for (const c of callablesOf(instances)) {
    for (let p = 0; p < c.arity; p++) {
      const args = new Array(c.arity).fill(0);
      args[p] = arrays[calls % arrays.length];
      judge(`${c.label} with a ${args[p].constructor.name}(${LARGE_ARRAY_LENGTH}) as argument ${p + 1}`, () => c.call(args));
      if (c.instance) answers(c.instance, instances[c.instance], c.label);
      calls += 1;
    }
  }
  for (const x of Object.values(instances)) x.free();
  coreIntact(numbers, pointers, `${calls} calls with large typed arrays (${Math.round(performance.now() - started)} ms)`);
});

// Loads the wasm core (the --target web package in pkg/) in Node, building it
// first when it is missing.
import fs from 'node:fs';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { fileURLToPath, pathToFileURL } from 'node:url';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

/**
 * A module of the core the page ships (pkg/): the chapter's widgets, or with
 * `logs` the real-log module (`RealLogSession`); with `bench`, one module
 * holding both and the benchmark workloads' entry points (pkg-bench/).
 * Built when missing (and, with `rebuild`, always: cargo makes that quick
 * when nothing changed).
 */
export async function loadCore({ bench = false, rebuild = false, logs = false } = {}) {
  const dir = bench ? 'pkg-bench' : 'pkg';
  const stem = logs && !bench ? 'occgrid_logs' : 'occgrid';
  const wasmPath = path.join(root, dir, `${stem}_bg.wasm`);
  if (rebuild || !fs.existsSync(wasmPath)) {
    execFileSync('bash', [path.join(root, 'scripts/build.sh'), ...(bench ? ['--bench'] : [])], { stdio: ['ignore', process.stderr, 'inherit'] });
  }
  const core = await import(pathToFileURL(path.join(root, dir, `${stem}.js`)).href);
  const exports = await core.default({ module_or_path: fs.readFileSync(wasmPath) });
  return { core, memory: exports.memory };
}

/** Runs every module of a folder (sorted by name) with `(core, args)`. */
export async function runModules(folder, core, args) {
  const dir = path.join(root, folder);
  const files = fs.readdirSync(dir).filter((f) => f.endsWith('.mjs')).sort();
  const results = [];
  for (const f of files) {
    const mod = await import(pathToFileURL(path.join(dir, f)).href);
    results.push(await mod.default(core, args));
  }
  return results;
}

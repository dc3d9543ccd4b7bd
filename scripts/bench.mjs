// Prints one JSON object per line for every workload of docs/BENCHMARKS.md:
// first the native figures (cargo bench --bench native), then the same work
// on the wasm build under Node (scripts/bench/*.mjs). An argument filters the
// workloads by name; a name that is a module of scripts/bench/ (e.g.
// logs-browser) runs that module alone, with the options after it.
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { spawnSync } from 'node:child_process';
import { loadCore, runModules, root } from './lib/load-core.mjs';

const args = process.argv.slice(2);
// The value of an option (--log PATH) is not a workload name.
const filter = args.find((a, i) => !a.startsWith('-') && args[i - 1] !== '--log');
const keep = (w) => !filter || String(w.workload).includes(filter);

const own = filter && /^[\w-]+$/.test(filter) && path.join(root, 'scripts/bench', `${filter}.mjs`);
if (own && fs.existsSync(own)) {
  // The page's two modules as one namespace: a workload of real logs finds
  // `RealLogSession` (the logs module), the others the chapter's classes.
  const core = { ...(await loadCore()).core, ...(await loadCore({ logs: true })).core };
  const rows = await (await import(pathToFileURL(own).href)).default(core, args);
  for (const row of rows) console.log(JSON.stringify(row));
  process.exit(process.exitCode ?? 0);
}

const native = spawnSync('cargo', ['bench', '--quiet', '--bench', 'native', '--', ...(filter ? [filter] : [])], {
  cwd: root,
  encoding: 'utf8',
  stdio: ['ignore', 'pipe', 'inherit'],
});
if (native.status !== 0) {
  console.error('bench: the native benchmark failed');
  process.exit(1);
}
for (const line of native.stdout.split('\n')) if (line.startsWith('{')) console.log(line);

// The workloads' entry points live in the bench build of the same core; the
// shipped one (pkg/, measured by wasm-size) must exist too.
await loadCore();
const { core } = await loadCore({ bench: true, rebuild: true });
for (const rows of await runModules('scripts/bench', core, process.argv.slice(2))) {
  for (const row of rows.filter(keep)) console.log(JSON.stringify(row));
}

// Prints one JSON object per line for every workload of BENCHMARKS.md:
// first the native figures (cargo bench --bench native), then the same work
// on the wasm build under Node (scripts/bench/*.mjs). An argument filters the
// workloads by name.
import { spawnSync } from 'node:child_process';
import { loadCore, runModules, root } from './lib/load-core.mjs';

const filter = process.argv.slice(2).find((a) => !a.startsWith('-'));
const keep = (w) => !filter || String(w.workload).includes(filter);

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

const { core } = await loadCore();
for (const rows of await runModules('scripts/bench', core, process.argv.slice(2))) {
  for (const row of rows.filter(keep)) console.log(JSON.stringify(row));
}

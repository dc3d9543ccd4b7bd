// Prints one JSON object of the chapter's numbers, every one computed by the
// wasm core under Node. Each key comes from a module in scripts/numbers/.
// A module may answer a specific query alone (e.g. `--joint FILE.json`) by
// returning `{ __only: value }`.
import { loadCore, runModules } from './lib/load-core.mjs';

const args = process.argv.slice(2);
try {
  const { core } = await loadCore();
  const parts = await runModules('scripts/numbers', core, args);
  const only = parts.find((p) => p && p.__only !== undefined);
  const out = only ? only.__only : Object.assign({}, ...parts);
  console.log(JSON.stringify(out, null, 2));
} catch (e) {
  console.error(`numbers: ${e && e.message ? e.message : e}`);
  process.exit(1);
}

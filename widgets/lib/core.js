// Loads the wasm core once per page, relative to this module, so a widget
// imported from another origin finds its wasm next to it. scripts/dist.mjs
// rewrites the two pkg/ specifiers below to the core's content-hashed names.
import init, * as core from '../../pkg/occgrid.js';

let loading = null;

/** Resolves to `{ core, memory }`: the core's functions and classes, and its memory. */
export function loadCore() {
  if (!loading) {
    const wasmUrl = new URL('../../pkg/occgrid_bg.wasm', import.meta.url);
    loading = init({ module_or_path: wasmUrl }).then((exports) => ({ core, memory: exports.memory }));
  }
  return loading;
}

// Loads the wasm core, relative to this module, so a widget imported from
// another origin finds its wasm next to it. The core is two modules of one
// crate: the chapter's widgets (loadCore), loaded once per page, and real
// laser logs (loadLogCore), loaded only when a reader opens Map Weaver's
// real-log mode, so that the page downloads no log code it does not use.
// scripts/dist.mjs rewrites the four pkg/ specifiers below to the content-
// hashed names; the log module's glue is imported on demand, not up front.
import init, * as core from '../../pkg/occgrid.js';

let loading = null;
let loadingLogs = null;

/** Resolves to `{ core, memory }`: the chapter core's functions and classes, and its memory. */
export function loadCore() {
  if (!loading) {
    const wasmUrl = new URL('../../pkg/occgrid_bg.wasm', import.meta.url);
    loading = init({ module_or_path: wasmUrl }).then((exports) => ({ core, memory: exports.memory }));
  }
  return loading;
}

/** Resolves to `{ core, memory }` of the real-log module (`RealLogSession`), its own memory. */
export function loadLogCore() {
  if (!loadingLogs) {
    const wasmUrl = new URL('../../pkg/occgrid_logs_bg.wasm', import.meta.url);
    loadingLogs = import('../../pkg/occgrid_logs.js')
      .then((logs) => logs.default({ module_or_path: wasmUrl }).then((exports) => ({ core: logs, memory: exports.memory })))
      .catch((e) => { loadingLogs = null; throw e; });
  }
  return loadingLogs;
}

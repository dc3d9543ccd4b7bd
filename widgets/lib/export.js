// Saving a map for ROS. Every widget's "Export map" button takes the
// map_server pair its binding returns (`exportMap(...)` → `{ pgm, yaml }`)
// and hands it to `downloadMapPair`, which saves ONE zip holding NAME.pgm
// and NAME.yaml, the YAML's `image:` line naming the PGM beside it (unzip,
// then `ros2 run nav2_map_server map_server --ros-args -p
// yaml_filename:=NAME.yaml`). One file rather than two because browsers
// hold back a page's second automatic download behind a permission prompt.
// The archive is packed by the core; this module only hands it to the
// browser.
import { loadCore } from './core.js';

/**
 * Downloads `pair` as NAME.zip. `name` is a file stem such as "intel-map"
 * (characters other than letters, digits, `.`, `_` and `-` become `_`).
 * Resolves to the file name used.
 */
export async function downloadMapPair(name, pair) {
  if (!pair || !(pair.pgm instanceof Uint8Array) || typeof pair.yaml !== 'string') {
    throw new Error('invalid map pair: expected { pgm: Uint8Array, yaml: string } from exportMap()');
  }
  const { core } = await loadCore();
  const { fileName, bytes } = core.zipMapPair(String(name ?? ''), pair.pgm, pair.yaml);
  const url = URL.createObjectURL(new Blob([bytes], { type: 'application/zip' }));
  const a = document.createElement('a');
  a.href = url;
  a.download = fileName;
  a.hidden = true;
  document.body.append(a);
  a.click();
  a.remove();
  // The download has started by the time the click returns; keep the URL a
  // little longer for browsers that read it lazily.
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
  return fileName;
}

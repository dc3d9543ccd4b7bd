// The size of the shipped core as the page downloads it, raw and gzipped at
// level 9, per wasm module (scripts/build.sh): `occgrid`, the chapter's
// widgets, which every page loads (the target: under 250 KB gzipped), and
// `occgrid_logs`, real laser logs, loaded only when a reader opens a log.
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { root } from '../lib/load-core.mjs';
import { round } from '../lib/stats.mjs';

const MODULES = [['occgrid', 'every page'], ['occgrid_logs', 'when a log is opened']];

export default async function () {
  return MODULES.map(([stem, loaded]) => {
    const bytes = fs.readFileSync(path.join(root, `pkg/${stem}_bg.wasm`));
    const gzipped = zlib.gzipSync(bytes, { level: 9 }).length;
    return {
      workload: 'wasm-size', runtime: 'wasm', module: stem, loaded,
      raw_bytes: bytes.length, gzip_bytes: gzipped, gzip_kb: round(gzipped / 1000, 1),
    };
  });
}

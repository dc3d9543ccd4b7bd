// The size of the shipped core: pkg/occgrid_bg.wasm as the page downloads
// it, raw and gzipped at level 9 (the target is under 250 KB gzipped for
// the whole core).
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { root } from '../lib/load-core.mjs';
import { round } from '../lib/stats.mjs';

export default async function () {
  const bytes = fs.readFileSync(path.join(root, 'pkg/occgrid_bg.wasm'));
  const gzipped = zlib.gzipSync(bytes, { level: 9 }).length;
  return [{
    workload: 'wasm-size', runtime: 'wasm',
    raw_bytes: bytes.length, gzip_bytes: gzipped, gzip_kb: round(gzipped / 1000, 1),
  }];
}

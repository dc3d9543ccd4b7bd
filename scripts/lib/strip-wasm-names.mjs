// Removes the custom sections nothing at run time reads (function names for
// debuggers, the producers, the target features) from a wasm module, in
// place. The names hold about a tenth of the module's bytes and
// nothing the page runs: panics still print their message through the
// panic hook.
import fs from 'node:fs';
import { leb } from './wasm-leb.mjs';

/** Custom sections nothing at run time reads: the function names, the
 * compiler's and tools' names and versions (`producers`), and the features
 * the compiler assumed (`target_features`, read only by linkers). */
const DROPPED = new Set(['name', 'producers', 'target_features']);

export function stripNames(bytes) {
  const keep = [bytes.subarray(0, 8)];
  let i = 8;
  while (i < bytes.length) {
    const start = i;
    const id = bytes[i++];
    const [size, body] = leb(bytes, i);
    const end = body + size;
    let drop = false;
    if (id === 0) {
      const [len, nameAt] = leb(bytes, body);
      drop = DROPPED.has(Buffer.from(bytes.subarray(nameAt, nameAt + len)).toString());
    }
    if (!drop) keep.push(bytes.subarray(start, end));
    i = end;
  }
  return Buffer.concat(keep);
}

const file = process.argv[2];
if (file) {
  const before = fs.readFileSync(file);
  const after = stripNames(before);
  await WebAssembly.compile(after); // refuse to write a module that does not validate
  fs.writeFileSync(file, after);
}

// The unsigned LEB128 numbers a wasm module's sections and entries are
// written in, read and written once for the build's steps over a module.

/** An unsigned LEB128 number at `i` of `bytes`: [value, the index after it]. */
export function leb(bytes, i) {
  let value = 0, shift = 0, b;
  do {
    b = bytes[i++];
    value += (b & 0x7f) * 2 ** shift;
    shift += 7;
  } while (b & 0x80);
  return [value, i];
}

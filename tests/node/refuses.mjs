// The Node tests' one assertion for refused calls.
import assert from 'node:assert/strict';

/** Asserts that `f` throws an Error whose message names every word. */
export function refuses(f, ...words) {
  let error;
  try {
    f();
  } catch (e) {
    error = e;
  }
  assert.ok(error instanceof Error, `expected an Error naming ${words.join(', ')}, got ${error}`);
  for (const w of words) assert.ok(error.message.includes(w), `${JSON.stringify(error.message)} should name ${w}`);
  return error.message;
}

// The real-log panel's build pace: the next build call's budget is sized
// from the slowest of the last few calls, so that a call of cheap units
// (a loop search's grid pass) does not size one of dear units (cell
// updates) two or three times past its slice; never more than twice the
// last budget.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { buildPace, readPace } from '../../widgets/lib/build-pace.js';

test('a fast call after slower ones does not raise the budget past the slowest pace', () => {
  const pace = buildPace(25);
  // 100 units a millisecond: 2,500 in a 25 ms slice.
  assert.equal(pace.next(2_500, 25, 2_500), 2_500);
  // Cheap units three times faster: the budget stays at the slow pace.
  assert.equal(pace.next(2_500, 25 / 3, 2_500), 2_500);
  assert.equal(pace.next(2_500, 25 / 3, 2_500), 2_500);
  assert.equal(pace.next(2_500, 25 / 3, 2_500), 2_500);
  // Four calls on, the slow one is forgotten: the fast pace, at most twice the last budget.
  assert.equal(pace.next(2_500, 25 / 3, 2_500), 5_000);
  assert.equal(pace.next(5_000, 50 / 3, 5_000), 7_500);
});

test('a slow call lowers the next budget at once, and a budget is never below 1', () => {
  const pace = buildPace(25);
  assert.equal(pace.next(10_000, 100, 10_000), 2_500);
  assert.equal(buildPace(25).next(10, 1e9, 0), 1);
});

// A log's read, as the Freiburg campus's at SLAM: lines read at 40 µs a
// scan, then a long run of cheap units (a source's start, a box grown),
// then the tiles the beams reach, 37 µs a scan. Sized from the last four
// calls, the cheap run grew the budget call after call and the tile walk's
// call ran far past its slice; sized from the slowest of the read's last
// 32 calls, it stays in its slice.
/**
 * Calls under `pace` from a budget of 32 units: 10 of lines read (40 µs a
 * unit), 12 of cheap units (2 µs), then 10 of tile walks (37 µs): the
 * tile walk's calls, in milliseconds.
 */
function campusRead(pace) {
  let n = 32;
  const call = (usPerUnit) => {
    const ms = (n * usPerUnit) / 1000;
    n = pace.next(n, ms, n);
    return ms;
  };
  for (let i = 0; i < 10; i++) call(40);
  for (let i = 0; i < 12; i++) call(2);
  return Array.from({ length: 10 }, () => call(37));
}

test("a read's calls stay in their slice after a long run of cheap units", () => {
  const longest = Math.max(...campusRead(readPace(25)));
  assert.ok(longest <= 25, `a tile walk's call took ${longest} ms`);
  // The last calls' pace alone lets it run far past its slice.
  assert.ok(campusRead(buildPace(25))[0] > 100);
});

test("one slow call of a read is forgotten 32 calls on", () => {
  const pace = readPace(25);
  // The first call, as the module warms up: 32 scans in 20 ms.
  let n = pace.next(32, 20, 32);
  assert.equal(n, 40);
  for (let i = 0; i < 31; i++) n = pace.next(n, n / 25, n);
  assert.equal(n, 40, 'held down while remembered');
  for (let i = 0; i < 4; i++) n = pace.next(n, n / 25, n);
  assert.ok(n > 300, `${n}`);
});

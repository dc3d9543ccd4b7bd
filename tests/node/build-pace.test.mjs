// The real-log panel's build pace: the next build call's budget is sized
// from the slowest of the last few calls, so that a call of cheap units
// (a loop search's grid pass) does not size one of dear units (cell
// updates) two or three times past its slice; never more than twice the
// last budget.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { buildPace } from '../../widgets/lib/build-pace.js';

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

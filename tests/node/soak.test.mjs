// Map Weaver soak under Node: 400,000 scans of the
// apartment lap in the release wasm build, driven frame by frame as the
// widget drives it, must not grow the wasm memory once the first run has
// reached its largest history. Needs pkg/ (npm run build; loadCore builds
// it when missing). OCCGRID_SOAK_SCANS shortens or lengthens the soak.
import test from 'node:test';
import assert from 'node:assert/strict';
import { runSoak } from '../../scripts/soak.mjs';

// 400,000 scans: the allocator settles after about 130,000 scans (with the
// ghost watch's and the budgeted stepping's state per run, two four-page
// steps were seen, at the ninth and tenth restarts: 12.31 → 12.81 MB), and
// nothing grew after it in the next 270,000. The last 60% starts at 160,000.
const SCANS = Number(process.env.OCCGRID_SOAK_SCANS ?? 400_000);
// 20 laps (the most a run may hold) is about 14,000 scans per run: the
// history every run keeps peaks within the first fifth of the soak.
const LAPS = 20;
const PAGE = 65_536;

test(`wasm memory stops growing over ${SCANS} Map Weaver scans`, { timeout: 10 * 60_000 }, async (t) => {
  const f = await runSoak({ scans: SCANS, laps: LAPS, every: 1000 });
  t.diagnostic(JSON.stringify({ ...f, samples: undefined }));
  assert.equal(f.scans, SCANS, 'every scan was integrated');
  assert.ok(f.runs >= 2 || SCANS < 15_000, `the soak restarted finished runs (${f.runs} runs)`);
  assert.ok(f.samples.every(([, mb]) => Number.isFinite(mb) && mb > 0));
  // Memory grows in 64 KiB pages. While the first runs restart, the
  // allocator may take a page or two more for fragmentation; after that
  // (the last 60%, 240,000 scans at the default length) at most one page
  // may appear, so a leak of about 0.28 bytes per scan or more fails.
  assert.ok(f.growth_last_60pct_bytes <= PAGE,
    `memory grew by ${f.growth_last_60pct_bytes} bytes over the last 60% of the soak: ${JSON.stringify(f.samples)}`);
  // A generous ceiling: the chapter's run needs about 12 MB.
  assert.ok(f.mb_end < 64, `${f.mb_end} MB at the end`);
});

// A setting changed while Map Weaver makes a new run is never lost, in
// Chromium. Choosing the robot's situation makes the run again (training,
// then the linked scans in slices); a reader who moves the left evidence
// strength meanwhile must find the new run mapping with it, not with the
// strength the rebuild started from. The change is made on a state of the
// rebuild (its count of linked scans integrated so far), many times in a
// row, with another process keeping a core busy.
import { test, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { openPage, shutdown } from './harness.mjs';

after(shutdown);

const W = 'occgrid-map-weaver';
const ROUNDS = 10;

test('a strength moved during a rebuild reaches the new run, round after round, with a core kept busy', async () => {
  // Another process spinning on a core, as on a reader's busy laptop.
  const spinner = spawn(process.execPath, ['-e', 'for (;;) {}'], { stdio: 'ignore' });
  try {
    const { page, errors, close } = await openPage(`/?map-weaver.situation=ghost-watch&map-weaver.right-model=hand-crafted&map-weaver.left-strength=0.5&map-weaver.right-strength=0.5&map-weaver.right-clamp=6&map-weaver.scans=300&map-weaver.autoplay=off#${W}`,
      { viewport: { width: 1280, height: 800 }, reducedMotion: 'reduce' });
    await page.locator(W).scrollIntoViewIfNeeded();
    await page.waitForFunction((t) => document.querySelector(t).weaver?.readout().scans === 300, W, { timeout: 120_000 });
    const strengths = await page.evaluate((t) => {
      const input = document.querySelector(`${t} input[name=strength-left]`);
      return [Number(input.min), Number(input.max)];
    }, W);
    let raced = 0;
    for (let round = 0; round < ROUNDS; round++) {
      const situation = round % 2 === 0 ? 'lap' : 'ghost-watch';
      // Alternately the slider's two ends, so that every round changes it.
      const strength = strengths[round % 2 === 0 ? 1 : 0];
      // The slider moves on a state of the rebuild: once its fast-forward
      // has integrated at least 0, 100 or 200 of the 300 linked scans (or,
      // should it finish in one slice, as soon as it is over).
      const from = [0, 100, 200][round % 3];
      const moved = await page.evaluate(([t, s, v, at]) => new Promise((resolve) => {
        const w = document.querySelector(t);
        const old = w.weaver;
        let forwarding = false;
        const watch = new MutationObserver(() => {
          const ff = w.dataset.fastForward;
          if (ff !== undefined) forwarding = true;
          const due = ff !== undefined ? Number(ff.split('/')[0]) >= at : forwarding;
          if (!due) return;
          watch.disconnect();
          const input = w.querySelector('input[name=strength-left]');
          input.value = String(v);
          input.dispatchEvent(new Event('input', { bubbles: true }));
          resolve({ during: w.weaver === old });
        });
        watch.observe(w, { attributes: true, childList: true, subtree: true, characterData: true });
        const menu = w.querySelector('select[name=situation]');
        menu.value = s;
        menu.dispatchEvent(new Event('change', { bubbles: true }));
      }), [W, situation, strength, from]);
      raced += moved.during ? 1 : 0;
      // The new run is on screen once its linked scans are in and no pane still rebuilds.
      await page.waitForFunction(([t, s]) => {
        const w = document.querySelector(t);
        const r = w.weaver?.readout();
        return w.values.situation === s && w.dataset.fastForward === undefined && r?.scans === 300 && !/Training|Integrating/.test(w.status.textContent);
      }, [W, situation], { timeout: 120_000 });
      const state = await page.evaluate((t) => {
        const w = document.querySelector(t);
        return { core: w.weaver.readout().panes[0].strength, slider: Number(w.querySelector('input[name=strength-left]').value), option: w.options.panes[0].strength };
      }, W);
      assert.deepEqual(state, { core: strength, slider: strength, option: strength }, `round ${round} (${situation}, moved after ${from} scans)`);
    }
    // The rounds did move the slider while the new run was being made.
    assert.ok(raced >= ROUNDS / 2, `${raced} of ${ROUNDS} rounds moved the slider during the rebuild`);
    assert.deepEqual(errors, []);
    await close();
  } finally {
    spinner.kill();
  }
});

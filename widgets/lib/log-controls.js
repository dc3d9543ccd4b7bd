// The settings controls of Map Weaver's real-log panel
// (widgets/map-weaver-log.js): the resolution, Table 9.2's sliders, the
// no-return reach, the walls', poses' and cell models' menus and the seed
// of the odometry noise. Every range, step, name and menu's words is the
// core's table (`constants().limits.realLog`, src/apps/limits.rs); the range
// cap's slider ends where the core's reach does at the resolution in force.
import { el, slider, select, showError, fixed, nextId } from './ui.js';
import { modelControls } from './log-models.js';

/** What the seed field accepts (the core's MAX_SEED: a JavaScript number's whole range). */
const SEED_TEXT = /^\d{1,16}$/;

/**
 * The longest range cap `core` (the real-log module) takes at
 * `resolution`, whole metres (the table's, at the default resolution, if
 * it refuses the resolution: it says why at the load).
 */
function rangeCapMax(core, resolution, limits) {
  try {
    return Math.floor(core.RealLogSession.limits(resolution).rangeCapMax);
  } catch {
    return limits.rangeCap.max;
  }
}

/** A menu's options from the core's choices (`[{ value, caption }]`). */
const menu = (choices) => choices.map(({ value, caption }) => [String(value), caption]);

/**
 * The panel's settings controls, by settings field: each shows
 * `panel.settings` and calls `panel.change(patch)` when moved.
 */
export function settingsControls(panel) {
  const s = panel.settings;
  const k = panel.limits;
  const change = (patch) => panel.change(patch);
  const m = (v) => `${fixed(v, 2)} m`;
  /** A slider over the core's range of `key`. */
  const knob = (key, label, format, name) => slider({ label, ...k[key], value: s[key], format, onInput: (v) => change({ [key]: v }), name });
  return {
    resolution: select('Resolution', menu(k.resolutions), String(s.resolution), (v) => change({ resolution: Number(v) }), { name: 'resolution' }),
    rangeCap: slider({
      label: 'z_max (range cap)', ...k.rangeCap, max: rangeCapMax(panel.core, s.resolution, k), value: s.rangeCap,
      format: (v) => `${v} m`, onInput: (v) => change({ rangeCap: v }), name: 'range-cap',
    }),
    alpha: knob('alpha', 'α (obstacle depth)', m, 'alpha'),
    lOcc: knob('lOcc', 'l_occ', (v) => fixed(v, 2), 'l-occ'),
    lFree: knob('lFree', 'l_free', (v) => fixed(v, 2), 'l-free'),
    clamp: knob('clamp', 'clamp l_max', (v) => fixed(v, 1), 'clamp'),
    noReturnReach: knob('noReturnReach', 'no-return reach', (v) => `${v} m`, 'no-return-reach'),
    walls: select('Free evidence near walls', menu(k.walls), s.walls, (v) => change({ walls: v }), { name: 'walls' }),
    poses: select('Poses', menu(k.poses), s.poses, (v) => change({ poses: v }), { name: 'poses' }),
    seed: seedControl(panel, s.seed, k.maxSeed),
    ...modelControls(s, change, k.models),
  };
}

/** The seed of dead reckoning's noise, typed in: a text that is no whole number up to `max` is refused by name. */
function seedControl(panel, seed, max) {
  const id = nextId('real-log-seed');
  const input = el('input', { type: 'number', id, name: 'seed', min: 0, max, step: 1, value: String(seed), inputmode: 'numeric' });
  input.addEventListener('change', () => {
    const text = input.value.trim();
    const v = Number(text);
    if (!SEED_TEXT.test(text) || !Number.isSafeInteger(v) || v > max) {
      showError(panel.root, new Error(`seed ${JSON.stringify(input.value)} is not a whole number from 0 to ${max}`), 'settings: ');
      input.value = String(panel.settings.seed);
      return;
    }
    panel.change({ seed: v });
  });
  const root = el('div', { class: 'occgrid-control' }, el('label', { for: id }, 'Seed of the odometry noise'), input);
  return { root, input };
}

// Small building blocks shared by the widgets: labelled controls, hi-DPI
// canvases, error boxes, visibility, pacing and motion preferences (map
// panes are widgets/lib/pane.js, their drawing widgets/lib/layers.js).
// Nothing here computes a model number.

const stylesheet = new URL('./occgrid.css', import.meta.url).href;

/** Adds the widgets' stylesheet to the document once. */
export function ensureStyles(href = stylesheet) {
  if (document.querySelector(`link[data-occgrid-style="${href}"]`)) return;
  const link = document.createElement('link');
  link.rel = 'stylesheet';
  link.href = href;
  link.dataset.occgridStyle = href;
  document.head.append(link);
}

/** `el('div', { class: 'x', onclick: f }, child, 'text')` */
export function el(tag, props = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (v === undefined || v === null || v === false) continue;
    if (k.startsWith('on') && typeof v === 'function') node.addEventListener(k.slice(2), v);
    else if (k === 'class') node.className = v;
    else if (k === 'dataset') Object.assign(node.dataset, v);
    else if (k === 'text') node.textContent = v;
    else node.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children.flat()) if (c !== null && c !== undefined && c !== false) node.append(c);
  return node;
}

let uid = 0;
/** A unique id for label/for and aria links. */
export const nextId = (prefix = 'occgrid') => `${prefix}-${++uid}`;

/**
 * A labelled range slider with a live value readout.
 * Returns `{ root, input, value, set(v) }`; `onInput(value)` on change.
 */
export function slider({ label, min, max, step, value, format = String, onInput, name }) {
  const id = nextId('slider');
  const input = el('input', { type: 'range', id, min, max, step, value, name });
  const out = el('output', { for: id, 'aria-live': 'off' }, format(Number(value)));
  const root = el('div', { class: 'occgrid-control occgrid-slider' }, el('label', { for: id }, label), input, out);
  const update = () => {
    out.textContent = format(Number(input.value));
    input.setAttribute('aria-valuetext', out.textContent);
  };
  input.addEventListener('input', () => {
    update();
    onInput && onInput(Number(input.value));
  });
  update();
  return {
    root,
    input,
    get value() { return Number(input.value); },
    set(v) { input.value = v; update(); },
    /**
     * Takes the range `{ min, max, step }` (the core's, once it has
     * loaded), keeping the value shown where the range allows.
     */
    setRange({ min, max, step }) {
      const v = input.value;
      Object.assign(input, { min: String(min), max: String(max), step: String(step) });
      input.value = v;
      update();
    },
  };
}

/** A button; `label` is its visible text, `title` an optional longer description. */
export function button(label, onClick, { title, name, pressed } = {}) {
  const b = el('button', { type: 'button', title, name, 'aria-pressed': pressed === undefined ? undefined : String(pressed) }, label);
  b.addEventListener('click', onClick);
  return b;
}

/** A labelled checkbox. Returns `{ root, input, checked }`. */
export function toggle(label, checked, onChange, { name } = {}) {
  const id = nextId('toggle');
  const input = el('input', { type: 'checkbox', id, name });
  input.checked = checked;
  input.addEventListener('change', () => onChange(input.checked));
  const root = el('div', { class: 'occgrid-control occgrid-toggle' }, input, el('label', { for: id }, label));
  return { root, input, get checked() { return input.checked; } };
}

/** A labelled select. `options` is a list of [value, text]. */
export function select(label, options, value, onChange, { name } = {}) {
  const id = nextId('select');
  const input = el('select', { id, name }, options.map(([v, t]) => el('option', { value: v }, t)));
  input.value = value;
  input.addEventListener('change', () => onChange(input.value));
  const root = el('div', { class: 'occgrid-control occgrid-select' }, el('label', { for: id }, label), input);
  return { root, input };
}

/**
 * Most device pixels per CSS pixel a canvas gets. Past two, lines and text
 * look no sharper, and every changed canvas is copied whole to the screen
 * each frame: a phone's 3× screen would copy 2.25 times the pixels of 2×.
 */
export const MAX_CANVAS_SCALE = 2;
/**
 * Most device pixels of a map pane redrawn while a widget plays, on a
 * small screen (SMALL_SCREEN, a phone; about 350 × 350). Measured on a
 * 390 px phone at 3× with the CPU throttled 4×: four panes of the sensor
 * fusion widget redrawn a dozen times a second hold 30 frames a second at
 * this size, and about 10 at the screen's full ratio, where copying the
 * canvases to the screen takes most of every frame.
 */
export const MAX_ANIMATED_CANVAS_PIXELS = 120_000;
/** A phone's screen, in CSS pixels. */
export const SMALL_SCREEN = '(max-width: 600px)';

/** True on a small screen (SMALL_SCREEN). */
export function smallScreen() {
  return window.matchMedia?.(SMALL_SCREEN).matches ?? false;
}

/**
 * Device pixels per CSS pixel for a `cssWidth x cssHeight` canvas: the
 * screen's ratio, at most MAX_CANVAS_SCALE and at most what keeps the
 * backing store within `maxPixels`, never below 1.
 */
export function canvasScale(cssWidth, cssHeight, { ratio = window.devicePixelRatio || 1, maxPixels = Infinity } = {}) {
  const fit = Math.sqrt(maxPixels / Math.max(1, cssWidth * cssHeight));
  return Math.max(1, Math.min(ratio, MAX_CANVAS_SCALE, fit));
}

/**
 * Sizes a canvas for the screen's pixel ratio so lines and text stay sharp
 * (within the budget of `canvasScale`, `maxPixels` device pixels):
 * `cssWidth x cssHeight` CSS pixels, drawn in CSS-pixel units.
 */
export function hiDpiCanvas(canvas, cssWidth, cssHeight, { maxPixels = Infinity } = {}) {
  const scale = canvasScale(cssWidth, cssHeight, { maxPixels });
  canvas.width = Math.round(cssWidth * scale);
  canvas.height = Math.round(cssHeight * scale);
  canvas.style.width = `${cssWidth}px`;
  canvas.style.aspectRatio = `${cssWidth} / ${cssHeight}`;
  const ctx = canvas.getContext('2d');
  ctx.setTransform(canvas.width / cssWidth, 0, 0, canvas.height / cssHeight, 0, 0);
  return ctx;
}

/**
 * Sets `node`'s text (or, with `attribute`, that attribute) only when it
 * changes: a readout rewritten with the same words every frame still costs
 * the page a style and layout pass.
 */
export function setText(node, text, attribute = null) {
  if (attribute === null) {
    if (node.textContent !== text) node.textContent = text;
  } else if (node.getAttribute(attribute) !== text) {
    node.setAttribute(attribute, text);
  }
}

/** The box of `showError`; attribute problems have their own (widgets/lib/attributes.js). */
const RUNTIME_ERROR = ':scope > .occgrid-error:not(.occgrid-attribute-error)';

/** Shows an error inside the widget (and in the console), instead of a blank box. */
export function showError(host, error, context = '') {
  const message = error && error.message ? error.message : String(error);
  console.error(`${widgetName(host)}: ${context}${message}`);
  let box = host.querySelector(RUNTIME_ERROR);
  if (!box) {
    box = el('div', { class: 'occgrid-error', role: 'alert' });
    // Below the attribute reports (widgets/lib/attributes.js), if any.
    const reports = host.querySelectorAll(':scope > .occgrid-attribute-error, :scope > .occgrid-attribute-warning');
    if (reports.length) reports[reports.length - 1].after(box);
    else host.prepend(box);
  }
  box.textContent = `${context}${message}`;
  return box;
}

/** The widget `host` belongs to (its own tag, or the nearest custom element's around it), as the console names it. */
function widgetName(host) {
  for (let e = host; e; e = e.parentElement) if (e.localName.includes('-')) return e.localName;
  return host.localName;
}

/** Clears an error shown by `showError`. */
export function clearError(host) {
  host.querySelector(RUNTIME_ERROR)?.remove();
}

/**
 * Calls `start` once, the first time `element` scrolls into view (with
 * `ahead`, once it is within half a screen of it: its work is done by the
 * time the reader gets there).
 */
export function whenVisible(element, start, { ahead = false } = {}) {
  if (!('IntersectionObserver' in window)) return void start();
  const io = new IntersectionObserver((entries) => {
    if (entries.some((e) => e.isIntersecting)) {
      io.disconnect();
      start();
    }
  }, ahead ? { rootMargin: AHEAD } : {});
  io.observe(element);
}

/**
 * Resolves in a task of its own, after every turn asked for before it: a
 * widget awaits a turn before each step of its start (its controls, its
 * first run, its first drawing), so that the widgets of a page start one
 * step per task and the page paints and answers input in between, instead
 * of all of them starting in the one task that loads their modules.
 */
export function startTurn() {
  const turn = turns.then(nextTask);
  turns = turn;
  return turn;
}
let turns = Promise.resolve();

/**
 * Resolves in a new task: `scheduler.yield` where the browser has it (the
 * page's other tasks of the same priority do not jump ahead), a message
 * otherwise (unlike a timer, never clamped to 4 ms).
 */
export function nextTask() {
  if (globalThis.scheduler?.yield) return globalThis.scheduler.yield();
  return new Promise((resolve) => {
    const channel = new MessageChannel();
    channel.port1.onmessage = () => {
      channel.port1.close();
      resolve();
    };
    channel.port2.postMessage(null);
  });
}

/** How far below (and above) the screen `whenVisible(…, { ahead: true })` looks: half a screen. */
const AHEAD = '50% 0px 50% 0px';

/**
 * Tracks whether `element` is on screen: `onChange(visible)` each time it
 * changes. Returns a function that stops tracking.
 */
export function trackVisibility(element, onChange) {
  if (!('IntersectionObserver' in window)) {
    onChange(true);
    return () => {};
  }
  // Entries arrive in time order: the last one is the current state.
  const io = new IntersectionObserver((entries) => onChange(entries[entries.length - 1].isIntersecting));
  io.observe(element);
  return () => io.disconnect();
}

/**
 * An animation loop that works only while `element` is on screen: each
 * frame calls `step(dtMs)` with the time since the previous frame (0 on
 * the first frame after a start or a return to the screen, at most 250 ms);
 * `step` returns false to end the loop. Off screen the loop stops asking
 * for frames altogether (and a hidden tab gets none), so a widget scrolled
 * away costs nothing; it resumes where it was when it comes back.
 * Returns `{ start(), stop(), running }`.
 */
export function frameLoop(element, step) {
  let running = false;
  let onScreen = false;
  let raf = 0;
  let last = 0;
  let untrack = null;
  const frame = (now) => {
    raf = 0;
    if (!running || !onScreen) return;
    const dt = last ? Math.min(now - last, 250) : 0;
    last = now;
    if (step(dt) === false) {
      stop();
      return;
    }
    if (running && onScreen && !raf) raf = requestAnimationFrame(frame);
  };
  const schedule = () => {
    if (running && onScreen && !raf) {
      last = 0;
      raf = requestAnimationFrame(frame);
    }
  };
  const stop = () => {
    running = false;
    if (raf) cancelAnimationFrame(raf);
    raf = 0;
  };
  return {
    start() {
      if (running) return;
      running = true;
      // The observer reports the element's visibility right after it starts.
      if (!untrack) {
        untrack = trackVisibility(element, (visible) => {
          onScreen = visible;
          if (visible) schedule();
          else if (raf) {
            cancelAnimationFrame(raf);
            raf = 0;
          }
        });
      }
      schedule();
    },
    stop,
    get running() { return running; },
    /** True while the loop is running and actually receiving frames. */
    get active() { return running && onScreen; },
  };
}

/** Shows a play button's state: "Pause" while playing, "Play" otherwise, and `aria-pressed` to match. */
export function showPlaying(button, playing) {
  button.textContent = playing ? 'Pause' : 'Play';
  button.setAttribute('aria-pressed', String(playing));
}

/**
 * Paces steps at `perSecond` over animation frames: `take(dt, speed)`
 * returns the whole steps that `dt` ms owe at `speed` times the rate, at
 * most `maxPerFrame` (the rest stays owed, so a slow frame catches up
 * later); `reset(owed)` forgets what is owed, or owes `owed` steps (1:
 * the first step comes with the next frame).
 */
export function pacer(perSecond, maxPerFrame) {
  let owed = 0;
  return {
    reset(initial = 0) { owed = initial; },
    /** Owes again `n` of the items taken that were not done (a frame whose work budget ran out), up to a frame's worth. */
    giveBack(n) { owed = Math.min(maxPerFrame, owed + Math.max(0, n)); },
    take(dt, speed = 1) {
      owed += (dt / 1000) * perSecond * speed;
      const n = Math.min(maxPerFrame, Math.floor(owed));
      owed -= n;
      return n;
    },
  };
}

/** True when the reader asked for reduced motion: animations wait for "play". */
export function prefersReducedMotion() {
  return window.matchMedia?.('(prefers-reduced-motion: reduce)').matches ?? false;
}

/** Formats a number with `d` decimals, keeping the sign visible. */
export function fixed(x, d = 4) {
  if (!Number.isFinite(x)) return String(x);
  const s = x.toFixed(d);
  return s === `-${(0).toFixed(d)}` ? (0).toFixed(d) : s;
}

/**
 * Formats a count or a measure with thousands separators and `d` decimals
 * ("2,000 cells", "11,389 ms"), as en-US number formatting writes it: the
 * one way the widgets write numbers of four digits and more.
 */
export function grouped(x, d = 0) {
  if (!Number.isFinite(x)) return String(x);
  // By hand rather than with Intl.NumberFormat: the first formatter a page
  // makes loads the locale's data, a long task on a slow phone while the
  // widgets build. As en-US formatting does, it rounds the number's
  // shortest decimal form half away from zero, and keeps the sign of -0.
  const sign = x < 0 || Object.is(x, -0) ? '-' : '';
  const [mantissa, exponent] = Math.abs(x).toExponential().split('e');
  let digits = mantissa.replace('.', '');
  // Digits before the decimal point; a number below 0.1 gets leading zeros.
  let point = Number(exponent) + 1;
  if (point < 0) {
    digits = '0'.repeat(-point) + digits;
    point = 0;
  }
  const keep = point + d;
  let kept = digits.slice(0, keep).padEnd(keep, '0');
  if (digits.length > keep && digits[keep] >= '5') {
    const up = kept.split('');
    let i = up.length - 1;
    for (; i >= 0 && up[i] === '9'; i--) up[i] = '0';
    if (i < 0) up.unshift('1');
    else up[i] = String(Number(up[i]) + 1);
    kept = up.join('');
  }
  const whole = (kept.slice(0, kept.length - d).replace(/^0+(?=\d)/, '') || '0').replace(/\B(?=(\d{3})+(?!\d))/g, ',');
  return sign + whole + (d > 0 ? `.${kept.slice(kept.length - d)}` : '');
}

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
 * Sizes a canvas for the screen's pixel ratio so lines and text stay sharp:
 * `cssWidth x cssHeight` CSS pixels, drawn in CSS-pixel units.
 */
export function hiDpiCanvas(canvas, cssWidth, cssHeight) {
  const dpr = Math.max(1, window.devicePixelRatio || 1);
  canvas.width = Math.round(cssWidth * dpr);
  canvas.height = Math.round(cssHeight * dpr);
  canvas.style.width = `${cssWidth}px`;
  canvas.style.aspectRatio = `${cssWidth} / ${cssHeight}`;
  const ctx = canvas.getContext('2d');
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  return ctx;
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
 * ("2,000 cells", "11,389 ms"): the one way the widgets write numbers of
 * four digits and more.
 */
export function grouped(x, d = 0) {
  if (!Number.isFinite(x)) return String(x);
  // One formatter per number of decimals: toLocaleString makes one per
  // call, too slow for readouts redrawn every frame.
  let f = formatters.get(d);
  if (!f) formatters.set(d, (f = new Intl.NumberFormat('en-US', { minimumFractionDigits: d, maximumFractionDigits: d })));
  return f.format(x);
}
const formatters = new Map();

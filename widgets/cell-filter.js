// <occgrid-cell-filter>: one cell's binary Bayes filter, reading by reading
// (Table 9.1, line 4). The reader clicks "occupied" / "free" readings and
// sees step, reading, l and p, every number computed by the wasm core. The
// default is the chapter's worked example; the "forget to subtract l0"
// toggle shows why the prior must be removed once per update.
//
// Attributes (see `attributeSpec` below and the README's "Embedding"):
// p-occ, p-free, prior (probabilities on the sliders' steps), clamp (a
// number of log odds, or "off"), readings (a string of o/f letters, e.g.
// "oof"), forget-l0 ("on"/"off"), controls.
import { startWidget } from './lib/start.js';
import { lineChart, COLORS } from './lib/chart.js';
import { el, slider, button, toggle, showError, clearError, fixed, grouped } from './lib/ui.js';
import { applyControls, controlGroups, flag, formatControls, invalidValue, number, probability } from './lib/attributes.js';
import { copyLinkControl } from './lib/state.js';
import { CELL_FILTER_DEFAULTS as DEFAULTS } from './lib/defaults.js';

// The two presets (the chapter's worked example, the l0 lesson) and the
// clamp are the core's (`constants().cellFilter`). The attributes' defaults
// are the worked example, written in lib/defaults.js because the sliders
// are built before the core has loaded.
const GROUPS = ['readings', 'presets', 'sliders', 'toggles', 'link'];

/**
 * The most readings the widget takes, from an attribute, a link or the
 * buttons: a lesson read row by row (the core's own budget,
 * `MAX_READINGS` of src/mapping/cell_filter.rs, is ten times larger).
 */
const MAX_READINGS = 1000;
/** The table shows the prior and at most this many of the latest readings. */
const TABLE_ROWS = 50;

const readingsType = {
  describe: `at most ${grouped(MAX_READINGS)} letters o for occupied and f for free, e.g. "oof"`,
  // Letters with a separator and a space each; longer is refused unread
  // (widgets/lib/attributes.js, parseBounded).
  maxLength: 3 * MAX_READINGS,
  parse(text, name) {
    const letters = text.replace(/[\s,]/g, '');
    // Refused on its length before a reading is parsed; the message cites
    // the count, not a kilobyte of letters.
    if (letters.length > MAX_READINGS) {
      throw new Error(`invalid ${name}: ${grouped(letters.length)} readings (expected ${this.describe})`);
    }
    const out = [];
    for (const ch of letters) {
      if (ch === 'o' || ch === 'O' || ch === '1') out.push(1);
      else if (ch === 'f' || ch === 'F' || ch === '0') out.push(0);
      else throw invalidValue(name, text, this.describe);
    }
    return out;
  },
};

const lettersOf = (readings) => readings.map((r) => (r ? 'o' : 'f')).join('');

/**
 * The clamp l_max's control, log odds: the core's range
 * (`constants().limits.cellFilter.clamp`), and then "off", where the update
 * saturates nowhere (the core takes Infinity for that). Until the core has
 * loaded, any number. The default is the core's
 * (`constants().cellFilter.workedExample.clamp`).
 */
const clampType = (range) => {
  const within = range ? number(range.min, range.max, { step: range.step }) : number(-Number.MAX_VALUE, Number.MAX_VALUE);
  return {
    describe: `${within.describe} (log odds), or "off" for no clamp`,
    parse(text, name) {
      if (text.trim().toLowerCase() === 'off') return Infinity;
      try {
        return within.parse(text, name);
      } catch {
        throw invalidValue(name, text, this.describe);
      }
    },
  };
};
const clampText = (clamp) => (clamp === Infinity ? 'off' : String(clamp));

/**
 * A probability as the table prints it: four decimals, or, where four
 * decimals would round it to 0 or 1, in powers of ten ("2.4 × 10⁻⁷",
 * "1 − 2.4 × 10⁻⁷"), so that a cell far out on either side still reads.
 */
function probabilityText(p) {
  if (!Number.isFinite(p) || (p >= 1e-3 && p <= 1 - 1e-3)) return fixed(p, 4);
  const away = p < 0.5 ? p : 1 - p;
  if (away === 0) return p < 0.5 ? '0' : '1';
  const [mantissa, exponent] = away.toExponential(1).split('e');
  const digits = { '-': '⁻', 0: '⁰', 1: '¹', 2: '²', 3: '³', 4: '⁴', 5: '⁵', 6: '⁶', 7: '⁷', 8: '⁸', 9: '⁹' };
  const power = `${mantissa} × 10${[...exponent.replace('+', '')].map((c) => digits[c]).join('')}`;
  return p < 0.5 ? power : `1 − ${power}`;
}

/**
 * A slider's range until the core's has loaded: the sliders show the
 * attributes' values at once, and the clamp's waits at "off" (its top).
 */
const UNTIL_CORE = { min: 0, max: 1, step: 'any' };

/** A probability slider's attribute type, on the core's steps (`constants().limits.cellFilter[key]`). */
const sliderType = (key) => (k) => ({ type: probability(k.limits.cellFilter[key]) });

/** Attribute name → the state field it sets. */
const FIELDS = { 'p-occ': 'pOcc', 'p-free': 'pFree', prior: 'prior', clamp: 'clamp', readings: 'readings', 'forget-l0': 'forget' };

class CellFilterElement extends HTMLElement {
  static attributeSpec = {
    // The sliders' ranges are the core's (`constants().limits.cellFilter`),
    // taken once it has loaded.
    'p-occ': { type: probability(), core: sliderType('pOcc'), default: DEFAULTS['p-occ'], doc: 'p(m | occupied reading): the inverse model’s answer to an occupied reading' },
    'p-free': { type: probability(), core: sliderType('pFree'), default: DEFAULTS['p-free'], doc: 'p(m | free reading): its answer to a free reading' },
    prior: { type: probability(), core: sliderType('prior'), default: DEFAULTS.prior, doc: 'the prior p(m), whose log odds is l0' },
    clamp: {
      type: clampType(null), doc: 'the clamp l_max: the update keeps |l| <= l_max (off: no clamp)',
      core: (k) => ({ type: clampType(k.limits.cellFilter.clamp), default: clampText(k.cellFilter.workedExample.clamp) }),
    },
    readings: { type: readingsType, default: DEFAULTS.readings, doc: 'the readings so far, in order' },
    'forget-l0': { type: flag(), default: DEFAULTS['forget-l0'], doc: 'start with the update that forgets to subtract l0' },
    controls: { type: controlGroups(GROUPS), default: 'all', doc: 'control groups shown: readings (the two reading buttons, undo, clear), presets (worked example, l0 lesson), sliders, toggles, link' },
  };

  static observedAttributes = Object.keys(CellFilterElement.attributeSpec);

  constructor() {
    super();
    // Filled from the attributes (their defaults: the worked example).
    this.state = {};
    this.ready = false;
    // The clamp slider's "off" notch and its step, the core's once loaded.
    this.clampOff = UNTIL_CORE.max;
    this.clampStep = 0;
  }

  connectedCallback() {
    // The table and its chart are made when the widget is first seen: a
    // reader opening the chapter waits for no widget below the screen.
    return startWidget(this, CellFilterElement.attributeSpec, {
      build: () => {
        this.applyAttributes(Object.keys(FIELDS));
        this.build();
        applyControls(this, this.values.controls);
      },
      withCore: (constants) => {
        this.presets = constants.cellFilter;
        this.takeRanges(constants.limits.cellFilter);
        // The sliders' values checked against the core's ranges, and the
        // clamp's default, the core's.
        this.values = this.attrs.resolve(constants);
        this.applyAttributes(['p-occ', 'p-free', 'prior', 'clamp']);
        this.syncControls();
        this.describeLesson();
      },
      whenSeen: () => {
        this.ready = true;
        this.render();
      },
    });
  }

  attributeChangedCallback(name) {
    if (!this.built) return;
    // The page set the model: what it says is not the reader's doing.
    if (name === 'p-occ' || name === 'p-free') this.modelByReader = false;
    this.applyAttributes([name]);
    if (name === 'controls') applyControls(this, this.values.controls);
    this.syncControls();
    this.render();
  }

  /**
   * Reads the attributes (a bad value is reported in the widget and the
   * last good one kept) and copies those named in `names` into the state.
   */
  /**
   * The sliders' ranges, the core's; the clamp's slider has one notch more
   * past its range: "off".
   */
  takeRanges(ranges) {
    for (const key of ['pOcc', 'pFree', 'prior']) this.sliders[key].setRange(ranges[key]);
    const { min, max, step } = ranges.clamp;
    this.clampStep = step;
    this.clampOff = max + step;
    this.sliders.clamp.setRange({ min, max: this.clampOff, step });
  }

  applyAttributes(names) {
    this.values = this.attrs.read();
    const next = { ...this.state };
    for (const n of names) {
      if (!(n in FIELDS)) continue;
      const v = this.values[n];
      next[FIELDS[n]] = Array.isArray(v) ? [...v] : v;
    }
    this.state = next;
  }

  /** The current state as attribute values, for "Copy link". */
  linkState() {
    const s = this.state;
    return {
      'p-occ': s.pOcc.toFixed(2), 'p-free': s.pFree.toFixed(2), prior: s.prior.toFixed(2),
      clamp: s.clamp === undefined ? null : clampText(s.clamp),
      readings: lettersOf(s.readings), 'forget-l0': s.forget ? 'on' : 'off',
      controls: formatControls(this.values.controls, GROUPS),
    };
  }

  build() {
    const s = this.state;
    this.sliders = {
      pOcc: slider({ label: 'p(m | occupied reading)', ...UNTIL_CORE, value: s.pOcc, format: (v) => v.toFixed(2), onInput: (v) => this.setModel({ pOcc: v }) }),
      pFree: slider({ label: 'p(m | free reading)', ...UNTIL_CORE, value: s.pFree, format: (v) => v.toFixed(2), onInput: (v) => this.setModel({ pFree: v }) }),
      prior: slider({ label: 'prior p(m)', ...UNTIL_CORE, value: s.prior, format: (v) => v.toFixed(2), onInput: (v) => this.set({ prior: v }) }),
      // Until the core has given its default and range, the slider waits at "off".
      clamp: slider({
        label: 'clamp l_max', ...UNTIL_CORE, value: UNTIL_CORE.max,
        format: (v) => (v >= this.clampOff - this.clampStep / 2 ? 'off (no clamp)' : `±${v.toFixed(1)}`),
        onInput: (v) => this.set({ clamp: v >= this.clampOff - this.clampStep / 2 ? Infinity : v }),
        name: 'clamp',
      }),
    };
    this.forgetToggle = toggle('forget to subtract l0', s.forget, (v) => this.set({ forget: v }), { name: 'forget-l0' });
    this.tbody = el('tbody');
    this.summary = el('p', { class: 'occgrid-readout', 'aria-live': 'polite' });
    this.bar = el('div');
    this.barBox = el('div', { class: 'cell-filter-bar', role: 'meter', 'aria-valuemin': '0', 'aria-valuemax': '1', 'aria-label': 'p, the probability that the cell is occupied' }, this.bar);
    this.barLabel = el('span', { class: 'cell-filter-bar-label' });
    // What a reader should not miss: the cell at the clamp, a full table,
    // an inverse model whose "free" answer says occupied.
    this.notices = el('ul', { class: 'cell-filter-notices', 'aria-live': 'polite' });
    this.addButtons = [
      button('Occupied reading', () => this.add(1), { name: 'occupied' }),
      button('Free reading', () => this.add(0), { name: 'free' }),
    ];
    this.chartBox = el('div', { class: 'cell-filter-chart', role: 'img', 'aria-label': 'log odds after each reading' });

    this.append(
      el('div', { class: 'occgrid-buttons' },
        el('div', { class: 'occgrid-buttons cell-filter-group', role: 'group', 'aria-label': 'readings', dataset: { controls: 'readings' } },
          ...this.addButtons,
          button('Undo', () => this.set({ readings: this.state.readings.slice(0, -1) }), { name: 'undo' }),
          button('Clear readings', () => this.set({ readings: [] }), { name: 'clear' })),
        el('div', { class: 'occgrid-buttons cell-filter-group', role: 'group', 'aria-label': 'presets', dataset: { controls: 'presets' } },
          button('Worked example', () => this.preset('workedExample'), { name: 'worked-example' }),
          this.lessonButton = button('The l0 lesson', () => this.preset('l0Lesson'), { name: 'l0-lesson' }))),
      el('div', { class: 'occgrid-controls' },
        el('div', { class: 'occgrid-controls cell-filter-group', dataset: { controls: 'sliders' } }, this.sliders.pOcc.root, this.sliders.pFree.root, this.sliders.prior.root, this.sliders.clamp.root),
        el('div', { class: 'occgrid-controls cell-filter-group', dataset: { controls: 'toggles' } }, this.forgetToggle.root)),
      el('div', { class: 'cell-filter-layout' },
        el('div', {},
          // The table scrolls once it is taller than the chart beside it.
          el('div', { class: 'occgrid-scroll cell-filter-scroll', tabindex: 0, role: 'region', 'aria-label': 'The cell after each reading' },
          el('table', { class: 'occgrid-table cell-filter-table' },
            el('caption', { class: 'occgrid-sr-only' }, 'The cell after each reading'),
            el('thead', {}, el('tr', {}, el('th', { scope: 'col' }, 'step'), el('th', { scope: 'col' }, 'reading'), el('th', { scope: 'col' }, 'l'), el('th', { scope: 'col' }, 'p'))),
            this.tbody)),
          el('div', { class: 'cell-filter-bar-row' }, el('span', { 'aria-hidden': 'true' }, 'p(occupied)'), this.barBox, this.barLabel),
          this.summary,
          this.notices),
        this.chartBox),
      el('p', { class: 'occgrid-caption' },
        'Each reading adds the inverse model’s log odds and removes the prior l0 once. ',
        'The inverse model answers with a posterior, which already contains the prior; forget to remove l0 and every reading counts the prior once more. ',
        this.lessonText = el('span')),
      copyLinkControl(this, CellFilterElement.attributeSpec, () => this.linkState()),
    );
    // The chart is made with the first table (when the widget is first seen).
    this.chart = null;
  }

  makeChart() {
    return lineChart(this.chartBox, {
      xLabel: 'step', yLabel: 'log odds l', wholeX: true,
      series: [{ label: 'l', color: COLORS.series[0] }, { label: 'l0', color: COLORS.l0, dash: [6, 4], width: 1.5 }],
      height: 200,
    });
  }

  /** The reader moved one of the inverse model's two answers. */
  setModel(patch) {
    this.modelByReader = true;
    this.set(patch);
  }

  /** Sets the core's preset `name` (nothing before the core has loaded). */
  preset(name) {
    const p = this.presets?.[name];
    if (!p) return;
    this.modelByReader = false;
    this.set({ pOcc: p.pOcc, pFree: p.pFree, prior: p.prior, clamp: p.clamp, readings: [...p.readings], forget: !p.subtractPrior });
  }

  /** The l0 lesson's caption and button title, in the core's numbers. */
  describeLesson() {
    const p = this.presets.l0Lesson;
    const l0 = fixed(this.core.runCellFilter(p.pOcc, p.pFree, p.prior, p.clamp, new Uint8Array(0), true).l0, 3).replace('-', '−');
    this.lessonButton.title = `prior ${p.prior}, alternating readings, without subtracting l0`;
    this.lessonText.textContent = `“The l0 lesson” uses a prior of ${p.prior} and answers of ${fixed(p.pOcc, 2)} / ${fixed(p.pFree, 2)}, symmetric around it: ` +
      `alternating readings keep the cell near l0 = ${l0}, but without the subtraction each reading adds another ${l0} and the cell drifts toward free.`;
  }

  syncControls() {
    const s = this.state;
    this.sliders.pOcc.set(s.pOcc);
    this.sliders.pFree.set(s.pFree);
    this.sliders.prior.set(s.prior);
    if (s.clamp !== undefined) this.sliders.clamp.set(s.clamp === Infinity ? this.clampOff : s.clamp);
    this.forgetToggle.input.checked = s.forget;
  }

  set(patch) {
    this.state = { ...this.state, ...patch };
    this.syncControls();
    this.render();
  }

  add(reading) {
    if (this.state.readings.length >= MAX_READINGS) {
      showError(this, new Error(`at most ${grouped(MAX_READINGS)} readings: undo or clear some first`));
      return;
    }
    this.set({ readings: [...this.state.readings, reading] });
  }

  render() {
    if (!this.ready) return;
    const s = this.state;
    let table;
    try {
      table = this.core.runCellFilter(s.pOcc, s.pFree, s.prior, s.clamp, new Uint8Array(s.readings), !s.forget);
      clearError(this);
    } catch (e) {
      showError(this, e);
      return;
    }
    const row = (step, reading, l, p, cls) =>
      el('tr', { class: cls, dataset: { l: String(l), p: String(p) } },
        el('td', {}, step), el('td', {}, reading), el('td', { class: 'cell-filter-l' }, fixed(l, 4)), el('td', { class: 'cell-filter-p' }, probabilityText(p)));
    const priorP = s.prior;
    // A bounded table: the prior, then the latest TABLE_ROWS readings (the
    // chart shows every one).
    const shown = table.steps.slice(-TABLE_ROWS);
    const hidden = table.steps.length - shown.length;
    this.tbody.replaceChildren(
      row('0', 'prior', table.l0, priorP, 'cell-filter-prior'),
      ...(hidden ? [el('tr', { class: 'cell-filter-hidden' }, el('td', { colspan: '4' }, `… ${grouped(hidden)} earlier reading${hidden === 1 ? '' : 's'} (in the chart)`))] : []),
      ...shown.map((st) => row(grouped(st.step), st.occupied ? 'occupied' : 'free', st.l, st.p)),
    );
    const last = table.steps.at(-1);
    const p = last ? last.p : priorP;
    this.bar.style.width = `${(p * 100).toFixed(1)}%`;
    this.barLabel.textContent = probabilityText(p);
    this.barBox.setAttribute('aria-valuenow', String(p));
    this.barBox.setAttribute('aria-valuetext', `p = ${probabilityText(p)}`);
    const full = s.readings.length >= MAX_READINGS;
    for (const b of this.addButtons) b.disabled = full;
    const notes = [];
    if (table.firstAtClamp !== null && table.firstAtClamp !== undefined) {
      const at = table.steps[table.firstAtClamp - 1];
      notes.push(['clamp', `At the clamp: from reading ${grouped(table.firstAtClamp)} on, l is held at the clamp of ±${fixed(table.clamp, 1)} (l = ${fixed(at.l, 4)}, p = ${probabilityText(at.p)}), ` +
        'so that a few contradicting readings can still move the cell; further readings the same way change nothing. Set the clamp higher, or off, to follow them.']);
    }
    // Only when it concerns what the reader did: a free reading among the
    // readings, or the reader's own move of an answer's slider. A page or
    // a link that lowers p(m | occupied reading) below the default "free"
    // answer, with only occupied readings, changes nothing this warns of.
    if (table.freeIsEvidenceForOccupied && (this.modelByReader || table.steps.some((st) => !st.occupied))) {
      notes.push(['inverted', `p(m | free reading) = ${fixed(s.pFree, 2)} is not below p(m | occupied reading) = ${fixed(s.pOcc, 2)}: ` +
        'a “free” reading is now at least as much evidence for occupied as an occupied one.']);
    }
    if (full) notes.push(['full', `The filter takes at most ${grouped(MAX_READINGS)} readings: undo or clear to add more.`]);
    this.notices.replaceChildren(...notes.map(([kind, text]) => el('li', { class: `cell-filter-notice cell-filter-notice-${kind}`, dataset: { kind } }, text)));
    this.dataset.notices = notes.map(([k]) => k).join(' ');
    this.summary.textContent =
      `l_occ = ${fixed(table.lOcc, 4)}, l_free = ${fixed(table.lFree, 4)}, l0 = ${fixed(table.l0, 4)}. ` +
      (last ? `After ${grouped(last.step)} reading${last.step === 1 ? '' : 's'}: l = ${fixed(last.l, 4)}, p = ${probabilityText(last.p)}.` : 'No readings yet.');
    this.dataset.l = last ? String(last.l) : String(table.l0);
    const xs = [0, ...table.steps.map((st) => st.step)];
    this.chart ??= this.makeChart();
    this.chart.setData(xs, [table.l0, ...table.steps.map((st) => st.l)], xs.map(() => table.l0));
    const ls = [table.l0, ...shown.map((st) => st.l)].map((v) => fixed(v, 2)).join(', ');
    this.chartBox.setAttribute('aria-label', `Log odds ${hidden ? `from the prior, then after the latest ${grouped(shown.length)} of ${grouped(table.steps.length)} readings` : 'after each reading'}: ${ls}; l0 = ${fixed(table.l0, 2)}`);
  }
}

if (!customElements.get('occgrid-cell-filter')) customElements.define('occgrid-cell-filter', CellFilterElement);

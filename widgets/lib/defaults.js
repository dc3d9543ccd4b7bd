// The model values a widget must state before its core has loaded: the
// cell filter's attribute defaults, which are the chapter's worked example
// and fill its sliders at once, and the defaults of Map Weaver's real-log
// panel, which its links are written against. Everything else the widgets
// take from the core's `constants()` when it has loaded (Map Weaver's
// simulation: `constants().mapWeaver`, its ranges and its chapter run);
// tests/node/constants.test.mjs checks that these, and the README's
// tables, say what the core says.

/** <occgrid-cell-filter>'s defaults: the core's `constants().cellFilter.workedExample`. */
export const CELL_FILTER_DEFAULTS = { 'p-occ': '0.70', 'p-free': '0.30', prior: '0.50', readings: 'oof', 'forget-l0': 'off' };

/**
 * <occgrid-map-weaver>'s real-log panel's defaults, written as a link
 * writes them: the core's `RealLogSession.defaultSettings()`. The panel
 * itself starts from the core's.
 */
export const MAP_WEAVER_LOG_DEFAULTS = {
  'log-resolution': '0.05', 'log-range-cap': '30', 'log-alpha': '0.10', 'log-l-occ': '0.85', 'log-l-free': '-0.40',
  'log-clamp': '3.5', 'log-no-return-reach': '5', 'log-walls': 'incidence', 'log-poses': 'corrected', 'log-seed': '1',
};

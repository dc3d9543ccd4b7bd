// <occgrid-map-weaver>'s attributes that the core bounds: each pane's
// settings (their ranges and defaults the core's `constants().mapWeaver`)
// and the real-log panel's (their ranges, names and menus the core's table,
// `constants().limits.realLog`). Until the core has loaded each is read
// with a looser type (widgets/lib/attributes.js, `core`).
import { ANY_NUMBER, flag, oneOf, steps, whole } from './attributes.js';
import { MAP_WEAVER_LOG_DEFAULTS as LOG_DEFAULTS } from './defaults.js';
import { LOG_MODEL_DEFAULT } from './log-models.js';
import { formatPane, logName } from './map-weaver-words.js';

/** A knob's range from the core (`constants().mapWeaver[key]`: `{ min, max, step }`). */
const coreSteps = (c, key, unit) => steps(c.mapWeaver[key], unit);

/**
 * Pane `k`'s attributes. Their defaults are the core's chapter run
 * (`constants().mapWeaver.defaults.panes[k]`), written as a link writes
 * the setting, and the numbers' ranges the core's limits: both taken once
 * the core has loaded.
 */
export const paneSpec = (side, k) => {
  const byDefault = (field) => (c) => ({ default: formatPane(field, c.mapWeaver.defaults.panes[k][field]) });
  const withRange = (field, key, unit) => (c) => ({ ...byDefault(field)(c), type: coreSteps(c, key, unit) });
  return {
    [`${side}-model`]: { type: oneOf(['hand-crafted', 'learned']), core: byDefault('model'), doc: `the ${side} map’s inverse model: Table 9.2 or the learned one of §9.3` },
    [`${side}-pose`]: { type: oneOf(['oracle', 'dead-reckoning']), core: byDefault('pose'), doc: `where the ${side} map takes the robot’s pose from: the true pose or the odometry` },
    [`${side}-clamp`]: { type: ANY_NUMBER, core: withRange('clamp', 'clamp'), doc: `the ${side} map’s clamp l_max, log odds` },
    [`${side}-strength`]: { type: ANY_NUMBER, core: withRange('strength', 'strength'), doc: `factor on the ${side} map’s evidence` },
    [`${side}-mapper`]: { type: oneOf(['traversal', 'sweep']), core: byDefault('mapper'), doc: `how the ${side} map applies Table 9.1: along each beam’s cells (traversal) or over every cell of the map (sweep)` },
    [`${side}-sensor`]: { type: oneOf(['lidar', 'cone']), core: byDefault('sensor'), doc: `how the ${side} map reads each range: a thin LiDAR beam, or a cone of opening ${side}-beta (Table 9.2’s β)` },
    [`${side}-beta`]: { type: ANY_NUMBER, core: withRange('betaDeg', 'betaDeg', '°'), doc: `the ${side} map’s cone opening β, degrees (with ${side}-sensor="cone")` },
    [`${side}-beams`]: {
      type: whole(1, Number.MAX_SAFE_INTEGER), core: (c) => ({ type: whole(1, c.mapWeaver.maxLidarBeams) }),
      doc: `beams of each scan the ${side} map uses, evenly spaced: a divisor of the LiDAR’s beam count (the core checks it against the scene); absent: all of them`,
    },
    [`${side}-resolution`]: {
      type: ANY_NUMBER, core: (c) => ({ type: oneOf(c.mapWeaver.paneResolutions.map(String), Number) }),
      doc: `the ${side} map’s cell size, metres; absent: the scene’s own`,
    },
    [`${side}-forget-l0`]: { type: flag(), core: byDefault('forgetL0'), doc: `the ${side} map adds the learned model’s scores without removing its l0 (exercise 8’s mistake)` },
  };
};

/** "none" is no second map. */
const noneIsNull = (w) => (w === 'none' ? null : w);
/** Any word: a menu's attribute until the core has named the choices. */
const anyWord = (map = (w) => w) => ({ describe: 'a word', parse: (text) => map(text.trim()) });
/** The real-log panel's table (`constants().limits.realLog`). */
const logLimits = (c) => c.limits.realLog;
/** A real-log slider's attribute: the core's `{ min, max, step }` of `key`. */
const logSteps = (key, unit) => (c) => ({ type: steps(logLimits(c)[key], unit) });
/** A real-log menu's attribute: one of the core's names of `key`, the default first. */
const logChoice = (key, map) => (c) => ({ type: oneOf(logLimits(c)[key].map((choice) => String(choice.value)), map) });

/**
 * The real-log panel's attributes (widgets/map-weaver-log.js). Their
 * defaults are written as a link writes them (widgets/lib/defaults.js,
 * checked against the core's by tests/node/constants.test.mjs).
 */
export const LOG_SPEC = {
  log: { type: logName, doc: 'real-log mode: the log of the server’s /datasets/ to load when the panel first comes into view; absent: the reader picks one' },
  'log-resolution': { type: ANY_NUMBER, core: logChoice('resolutions', Number), default: LOG_DEFAULTS['log-resolution'], doc: 'real-log mode: metres per cell' },
  'log-range-cap': { type: ANY_NUMBER, core: logSteps('rangeCap', 'm'), default: LOG_DEFAULTS['log-range-cap'], doc: 'real-log mode: z_max, metres; a reading at or beyond it is a no-return' },
  'log-alpha': { type: ANY_NUMBER, core: logSteps('alpha', 'm'), default: LOG_DEFAULTS['log-alpha'], doc: 'real-log mode: obstacle depth α of Table 9.2, metres' },
  'log-l-occ': { type: ANY_NUMBER, core: logSteps('lOcc'), default: LOG_DEFAULTS['log-l-occ'], doc: 'real-log mode: l_occ, log odds added at the reading' },
  'log-l-free': { type: ANY_NUMBER, core: logSteps('lFree'), default: LOG_DEFAULTS['log-l-free'], doc: 'real-log mode: l_free, log odds added in front of the reading' },
  'log-clamp': { type: ANY_NUMBER, core: logSteps('clamp'), default: LOG_DEFAULTS['log-clamp'], doc: 'real-log mode: the clamp l_max, log odds' },
  'log-no-return-reach': { type: ANY_NUMBER, core: logSteps('noReturnReach', 'm'), default: LOG_DEFAULTS['log-no-return-reach'], doc: 'real-log mode: how far a no-return clears free space, metres (at most z_max)' },
  'log-walls': { type: anyWord(), core: logChoice('walls'), default: LOG_DEFAULTS['log-walls'], doc: 'real-log mode: incidence (free evidence stops at the band of the wall a beam grazes) or table-9.2 (the chapter’s model: walls wear away on long logs)' },
  'log-poses': { type: anyWord(), core: logChoice('poses'), default: LOG_DEFAULTS['log-poses'], doc: 'real-log mode: the poses the scans are mapped at: corrected (the log’s own), dead-reckoning (the log’s motion increments with Table 5.6’s odometry noise, integrated; shown beside the corrected map) or scan-matched (that dead reckoning corrected by matching each scan against the map built so far; shown beside the corrected and dead-reckoned maps where they apply), or odometry (the log’s own: a ROS 2 bag’s)' },
  'log-seed': { type: whole(0, Number.MAX_SAFE_INTEGER), core: (c) => ({ type: whole(0, logLimits(c).maxSeed) }), default: LOG_DEFAULTS['log-seed'], doc: 'real-log mode: seed of dead reckoning’s odometry noise (one seed, one map)' },
  'log-model': { type: anyWord(), core: logChoice('models'), default: LOG_MODEL_DEFAULT, doc: 'real-log mode: what a cell believes: hit-counting (GMapping’s hits and visits), log-odds (Table 9.2 with the chapter’s clamp) or hit-miss-odds (Cartographer’s odds tables)' },
  'log-compare-model': {
    type: anyWord(noneIsNull), default: 'none', doc: 'real-log mode: a second map of the same log with another cell model, beside the first; none for one map',
    core: (c) => ({ type: oneOf(['none', ...logLimits(c).models.map((m) => m.value)], noneIsNull) }),
  },
};

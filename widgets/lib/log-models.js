// The real-log panel's cell models (docs/ARCHITECTURE.md, "Real logs"):
// what a cell of a real log's map believes, chosen by the reader (a select,
// the `log-model` attribute, `npm run export-map -- --model NAME`), and a
// second map of the same log with another model beside the first, as Map
// Weaver's two panes are (`log-compare-model`). The core builds and counts
// every map and names the models; this module makes their controls and says
// where each comes from.
import { el, select } from './ui.js';

/**
 * The real-log default, as a link writes it: the core's
 * `RealLogSession.defaultSettings().model` (tests/browser/real-log-models
 * checks that the two agree).
 */
export const LOG_MODEL_DEFAULT = 'hit-counting';

/** The panel's settings the two attributes stand for, and how a link writes each. */
export const LOG_MODEL_FIELDS = {
  'log-model': { field: 'model', format: (v) => String(v) },
  'log-compare-model': { field: 'compareModel', format: (v) => v ?? 'none' },
};

/**
 * The model's select and the comparison's, as the panel's controls (each
 * with `set(value)` for when the settings change elsewhere); `change` takes
 * a settings patch, `models` are the core's (`constants().limits.realLog.models`:
 * `[{ value, caption }]`, the default first).
 */
export function modelControls(settings, change, models) {
  const options = models.map(({ value, caption }) => [value, caption]);
  const model = select('Cell model', options, settings.model, (v) => change({ model: v }), { name: 'model' });
  const compare = select('Beside it, the same log with', [['', 'no second map'], ...options], settings.compareModel ?? '',
    (v) => change({ compareModel: v || null }), { name: 'compare-model' });
  return {
    model: { ...model, set: (v) => { model.input.value = String(v); } },
    compareModel: { ...compare, set: (v) => { compare.input.value = v ?? ''; } },
  };
}

/** What each model does and where it comes from, beside the panel's explanation of its settings. */
export function modelNote() {
  return el('p', { class: 'occgrid-caption map-weaver-log-models' },
    'Cell models. Hit counting (the default; GMapping’s “reflection map”, Grisetti, Stachniss & Burgard 2007, and Hector SLAM’s ',
    'GridMapReflectanceCount): each cell counts the beams that ended in it (hits) and the beams that passed through or ended in it ',
    '(visits), at most once per scan; it is occupied when more than a quarter of its visits are hits, free once visited with fewer, ',
    'unknown while never visited. One stray return among later beams through the cell leaves it free, and one beam through a cell ',
    'makes it white. Log odds is the chapter’s filter (Table 9.1 with Table 9.2’s l_occ and l_free and the clamp): one return makes a ',
    'cell black and four beams are needed to make one white. Hit/miss odds is Cartographer’s probability grid (Hess et al. 2016): a hit ',
    'multiplies a cell’s odds by odds(0.55), a miss by odds(0.49), within [0.1, 0.9], through lookup tables; its misses are so weak ',
    'that little of the floor would pass map_server’s free threshold (0.196), so its map is drawn, counted and exported free below ',
    'p 0.5 and occupied above it, as the exported YAML says. Under every model a beam is as wide as the beams’ spacing ',
    '(Table 9.2’s β), so floor between two beams, nearer than both readings, is free too, and beside a beam that saw nothing, the ',
    'half nearer a return is free out to that reading. Choose a second model to see both maps of the same log side by side.');
}

/** How a real log's map is made from its file, in words: the panel's caption under the maps. */
export function readingCaption() {
  return el('p', { class: 'occgrid-caption' },
    'A CARMEN log’s FLASER and ROBOTLASER1 lines are read with their corrected poses, a ROS 2 bag’s scans with its own odometry; ',
    'the map covers every pose and every cell a beam marks or clears, plus a metre. Each beam is traced cell by cell (Table 9.1) with the inverse model ',
    'of Table 9.2: l_occ within α/2 of the reading, l_free in front of it; a reading at or beyond z_max is a ',
    'no-return that only clears, out to the no-return reach, and only where the returns on both sides of it (at most 5° apart) saw free space; ',
    'a beam that reads beyond a surface its neighbours on both sides end on frees only what they do (glass, a grazed doorway). Near walls, free evidence stops where a beam ',
    'grazing a wall enters its band of cells (res / sin of the incidence), so long logs keep their walls; choose ',
    'Table 9.2 to see them wear away. Scrub back and the map is rebuilt from the first scan. ',
    'Poses: the log’s are corrected (the pose oracle); its odometry fields repeat them, so dead reckoning makes its own: ',
    'each motion between two scans, split into rotate, translate, rotate, gets the odometry noise of Table 5.6 (and the drift ',
    'of slightly unequal wheels) drawn from the seed, and the noisy motions are added up from the first pose. The ',
    'dead-reckoned map is drawn beside the corrected one: its walls double and its corridors bend. Scan-matched poses start from the same dead reckoning and move each scan to where it best fits the map built so far, before integrating it (while it builds, the scan’s returns are drawn where the match put them and a gray robot where the odometry predicted it); the corrected and dead-reckoned maps are drawn beside it. SLAM poses match each scan against a submap of recent scans, search finished submaps for loops, and optimise the pose graph when one closes; the map is then rebuilt at the new poses.');
}

// Builds the map of a CARMEN log or a ROS 2 bag (MCAP) with the wasm core
// under Node and writes it as a ROS map_server pair:
//
//   npm run export-map -- LOG OUT_PREFIX [--resolution M]
//     [--poses corrected|dead-reckoning|scan-matched|odometry|slam] [--seed N]
//     [--scan-topic T] [--odom-topic T]
//     [--model hit-counting|log-odds|hit-miss-odds]
//
// writes OUT_PREFIX.pgm and OUT_PREFIX.yaml (the YAML's `image:` names the
// PGM beside it), and OUT_PREFIX.poses.tsv, the poses the map was built
// with (one line per scan, `scan x y theta`, metres and radians), and prints a one-line JSON summary with the paths written.
// In the file name, characters other than letters, digits, `.`, `_` and `-`
// become `_`, so that the YAML can name the image without quoting. LOG may
// be gzipped.
// The map is the one Map Weaver's real-log mode builds, at its defaults: the
// grid covers the log's poses and readings, Table 9.2 with W1's weights and
// clamp, no-returns clearing 5 m (--no-return-reach), free evidence that
// stops at the wall a beam grazes (--walls incidence; table-9.2 for the
// chapter's model), 0.05 m cells (--resolution), at the log's own poses (a
// CARMEN log's corrected poses, a bag's odometry); `--poses dead-reckoning` maps it at dead-reckoned ones instead (the
// log's motion increments with Table 5.6's odometry noise, integrated from
// the first pose), the noise drawn from `--seed` (default 1; one seed, one
// map); `--poses scan-matched` starts from the same dead reckoning (or from
// the log's own odometry, where its odometry fields differ from its
// corrected poses) and corrects each scan's pose by matching the scan
// against the map built so far, before integrating it; `--poses slam` starts
// from the same odometry, matches each scan against a submap of recent scans,
// closes loops against finished submaps and optimises the pose graph (the map
// is built again at the optimised poses, which poses.tsv holds). `--model` chooses
// what a cell believes: hit-counting (the default: GMapping's hits and
// visits), log-odds (Table 9.2's filter with the chapter's clamp) or
// hit-miss-odds (Cartographer's odds tables).
// A bag (BAG.mcap) is mapped at its own odometry (`--poses odometry`, the
// default for a bag without --poses) or
// scan-matched from it; it has corrected poses only when it carries a
// `map → odom` transform (then `--poses corrected` applies, and is the
// default without --poses), and otherwise neither corrected nor dead
// reckoning applies to it (the core refuses a source that does not apply,
// by name). Its poses.tsv holds the laser's pose in the odometry frame
// (the map frame at corrected poses). A bag with several LaserScan or Odometry topics needs
// `--scan-topic` / `--odom-topic`; without them the core's refusal lists
// the bag's topics, types and message counts.
import fs from 'node:fs';
import path from 'node:path';
import { loadCore } from './lib/load-core.mjs';

const USAGE = 'usage: npm run export-map -- LOG OUT_PREFIX [--resolution M] [--no-return-reach M] [--walls incidence|table-9.2] [--poses corrected|dead-reckoning|scan-matched|odometry|slam] [--seed N] [--model hit-counting|log-odds|hit-miss-odds] [--scan-topic T] [--odom-topic T]';

/**
 * A number option's value: the text as given must be a decimal number
 * (`Number` would take '', '0x10' or ' 1 '; the core checks the range and
 * names the field). A text that is not a number is refused here, by name,
 * with the text itself, not as "NaN"; so is one that a double cannot hold
 * ('1e-400' would reach the core as 0, '1e999' as Infinity, and be refused
 * under a value the user never typed).
 */
function numberOption(name, text, what) {
  if (!/^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(text)) {
    throw new Error(`${name} ${JSON.stringify(text)} is not a number: expected ${what}\n${USAGE}`);
  }
  const value = Number(text);
  if (!Number.isFinite(value)) {
    throw new Error(`${name} ${text} is too large to be held as a number: expected ${what}\n${USAGE}`);
  }
  const mantissa = text.replace(/[eE].*$/, '');
  if (value === 0 && /[1-9]/.test(mantissa)) {
    throw new Error(`${name} ${text} is too small to be held as a number (it is not 0): expected ${what}\n${USAGE}`);
  }
  return value;
}

/** `--name VALUE` or `--name=VALUE` at argv[i]: the text and the next index. */
function optionText(argv, i, name, what) {
  const a = argv[i];
  const text = a.includes('=') ? a.slice(a.indexOf('=') + 1) : argv[i + 1];
  if (text === undefined) throw new Error(`${name} needs a value: ${what}\n${USAGE}`);
  return [text, a.includes('=') ? i : i + 1];
}

function parseArgs(argv) {
  const positional = [];
  const settings = {};
  const topics = {};
  const is = (a, name) => a === name || a.startsWith(`${name}=`);
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (is(a, '--resolution')) {
      const what = 'metres per cell, such as 0.05';
      let text;
      [text, i] = optionText(argv, i, '--resolution', what);
      settings.resolution = numberOption('--resolution', text, what);
    } else if (is(a, '--no-return-reach')) {
      const what = 'metres a no-return clears, such as 5';
      let text;
      [text, i] = optionText(argv, i, '--no-return-reach', what);
      settings.noReturnReach = numberOption('--no-return-reach', text, what);
    } else if (is(a, '--walls')) {
      let text;
      [text, i] = optionText(argv, i, '--walls', 'incidence or table-9.2');
      // The core names the field and the value it refuses.
      settings.walls = text;
    } else if (is(a, '--poses')) {
      let text;
      [text, i] = optionText(argv, i, '--poses', 'corrected, dead-reckoning, scan-matched, odometry or slam');
      // The core names the field and the value it refuses.
      settings.poses = text;
    } else if (is(a, '--scan-topic')) {
      [topics.scan, i] = optionText(argv, i, '--scan-topic', "a bag's LaserScan topic, such as /scan");
    } else if (is(a, '--odom-topic')) {
      [topics.odom, i] = optionText(argv, i, '--odom-topic', "a bag's Odometry topic, such as /odom");
    } else if (is(a, '--model')) {
      let text;
      [text, i] = optionText(argv, i, '--model', 'hit-counting, log-odds or hit-miss-odds');
      // The core names the field and the value it refuses.
      settings.model = text;
    } else if (is(a, '--seed')) {
      const what = 'a whole number from 0 to 9007199254740991, such as 7';
      let text;
      [text, i] = optionText(argv, i, '--seed', what);
      // Digits only: '1e3', '7.0' or '-1' would pass as numbers and then
      // be refused by the core under a name the command line did not use.
      if (!/^\d+$/.test(text)) throw new Error(`--seed ${JSON.stringify(text)} is not a whole number: expected ${what}\n${USAGE}`);
      const seed = Number(text);
      if (!Number.isSafeInteger(seed)) throw new Error(`--seed ${text} is too large: expected ${what}\n${USAGE}`);
      settings.seed = seed;
    } else if (a === '--help' || a === '-h') {
      console.log(USAGE);
      process.exit(0);
    } else if (a.startsWith('--')) {
      throw new Error(`unknown option: ${a}\n${USAGE}`);
    } else {
      positional.push(a);
    }
  }
  if (positional.length !== 2) throw new Error(`expected LOG and OUT_PREFIX, got ${positional.length} argument(s)\n${USAGE}`);
  return { log: positional[0], prefix: positional[1], settings, topics };
}

async function main() {
  const { log, prefix, settings, topics } = parseArgs(process.argv.slice(2));
  let bytes;
  try {
    bytes = fs.readFileSync(log);
  } catch (e) {
    throw new Error(`cannot read ${log}: ${e.message}`);
  }
  const { core } = await loadCore({ logs: true });
  const session = new core.RealLogSession(bytes);
  try {
    // Without --poses, the log's own: a CARMEN log's corrected poses, a bag's odometry.
    const posesGiven = settings.poses !== undefined;
    settings.poses ??= session.ownPoses();
    session.configure(settings);
    if (topics.scan !== undefined || topics.odom !== undefined) session.chooseTopics(topics.scan, topics.odom);
    // Each call reads a bounded step (scans, lines, bytes): loop to the end.
    let read;
    do read = session.read(1 << 30); while (!read.finished);
    if (read.warning) console.error(`export-map: warning: ${read.warning}`);
    // Without --poses, the read log's own: a bag's corrected poses when its
    // read found a map → odom transform.
    const own = session.ownPoses();
    if (!posesGiven && own && own !== settings.poses) {
      settings.poses = own;
      session.configure(settings);
      // A longer log's new panes are planned over calls of their own.
      if (session.state().state === 'planning') {
        let planned;
        do planned = session.plan(1 << 30); while (!planned.finished);
      }
    }
    // Pane 0 is the map at the chosen poses (a dead-reckoned or
    // scan-matched run also builds the maps the page shows beside it).
    let state;
    do state = session.buildSlice(Infinity); while (!state.finished);
    const built = state.panes[0];
    const stem = path.basename(prefix);
    // The YAML's comments name the log it was made from.
    const pair = session.exportMap(0, stem, path.basename(log));
    const dir = path.dirname(prefix);
    fs.mkdirSync(dir, { recursive: true });
    // The core names the image after the file stem; keep both files beside
    // each other under exactly that name.
    const image = /^image: (.*)$/m.exec(pair.yaml)?.[1];
    const pgmPath = path.join(dir, image && !image.startsWith('"') ? image : `${stem}.pgm`);
    const yamlPath = `${path.join(dir, path.basename(pgmPath, '.pgm'))}.yaml`;
    fs.writeFileSync(pgmPath, pair.pgm);
    fs.writeFileSync(yamlPath, pair.yaml);
    const posesPath = `${path.join(dir, path.basename(pgmPath, '.pgm'))}.poses.tsv`;
    fs.writeFileSync(posesPath, session.posesTsv(0));
    const g = session.geometry(0);
    const c = session.counts(0);
    console.log(JSON.stringify({
      log, warning: read.warning ?? undefined, poses: settings.poses ?? 'corrected', model: state.settings.model,
      seed: ['dead-reckoning', 'scan-matched', 'slam'].includes(settings.poses) ? (settings.seed ?? core.RealLogSession.defaultSettings().seed) : undefined, scans: built.scansTotal, beams: built.beams, cell_updates: built.cellUpdates,
      width: g.width, height: g.height, resolution: g.resolution, origin: [g.originX, g.originY],
      // Memory follows what the beams reached: cells allocated in tiles, of the bounding box.
      cells_allocated: built.cellsAllocated, bytes_allocated: built.bytesAllocated, cells: built.cells,
      // Counted with the YAML's own thresholds: what map_server loads.
      occupied: c.occupied, free: c.free, unknown: c.unknown,
      occupied_thresh: c.occupiedThresh, free_thresh: c.freeThresh, pgm: pgmPath, yaml: yamlPath, poses_tsv: posesPath,
    }));
  } finally {
    session.free();
  }
}

main().catch((e) => {
  console.error(`export-map: ${e.message ?? e}`);
  process.exit(1);
});

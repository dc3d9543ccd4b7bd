// The logs a `datasets/` folder offers the real-log panel, read from the
// table of its README.md (`| file | place | FLASER scans | … |`, as the
// project's datasets README has it): each log's file name and a
// descriptive name for the menu, "Intel Research Lab, Seattle (910 scans)";
// a ROS 2 bag (an MCAP file) by its file name and, when the table has a
// column headed from, the log it was made from.
// Only table rows count, so a README that names no log in its table lists
// none (a bundle ships such an empty listing; see scripts/dist.mjs).

/** A log's file name as the panel accepts it: one name, no path. */
const LOG_FILE = /^[\w-][\w.-]*\.((log|clf|txt)(\.gz)?|mcap)$/i;

/** The cells of a Markdown table row, or null for a line that is none. */
function cells(line) {
  const t = line.trim();
  if (!t.startsWith('|')) return null;
  return t.replace(/^\|/, '').replace(/\|$/, '').split('|').map((c) => c.trim().replace(/^`(.*)`$/, '$1'));
}

/** "the Radish “fhw” building" → "The Radish “fhw” building"; a trailing "(credit)" dropped. */
function placeName(text) {
  const t = text.replace(/\s*\([^()]*\)\s*$/, '').trim();
  return t.charAt(0).toUpperCase() + t.slice(1);
}

/**
 * `[[file, label]]` for every log of the README `text`'s table, in its
 * order: the label is the row's place and scan count when the table has
 * them ("place", "… scans" columns), else the file name.
 */
export function listedLogs(text) {
  const out = [];
  let header = null;
  for (const line of String(text).split('\n')) {
    const row = cells(line);
    if (!row) {
      header = null;
      continue;
    }
    if (row.every((c) => /^:?-{3,}:?$/.test(c))) continue;
    const file = row.findIndex((c) => LOG_FILE.test(c));
    if (file < 0) {
      header ??= row.map((c) => c.toLowerCase());
      continue;
    }
    const at = (pattern) => (header ? header.findIndex((h) => pattern.test(h)) : -1);
    const place = row[at(/^place$/)] ?? '';
    const scans = row[at(/scans/)] ?? '';
    const name = row[file];
    if (out.some(([n]) => n === name)) continue;
    const from = row[at(/^from$/)] ?? '';
    const bag = /\.mcap$/i.test(name);
    const label = bag
      ? `${name} (ROS 2 bag${from ? ` of ${from}` : ''})`
      : place ? `${placeName(place)}${/^[\d,]+$/.test(scans) ? ` (${scans} scans)` : ''}` : name;
    out.push([name, label]);
  }
  return out;
}

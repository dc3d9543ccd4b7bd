// The independence trap (docs/ARCHITECTURE.md, "The independence trap"): the chapter's two-cell case — cells A and
// B side by side at 2 m in one 22° sonar cone, prior 0.5, one reading of
// 2.0 m — and the collinear preset (A at 1 m and B at 2 m on the axis) —
// and, with `--joint FILE.json`, any query of the same form:
//   { "prior": 0.5, "beta_deg": 22, "cells": [{ "range": 2.0, "bearing_deg": -3 }, ...],
//     "readings": [2.0], "model": { optional forward-model fields } }
// answered alone as { joint, marginals, allFreeTrue, allFreeFactored }, the
// configurations ordered with the first cell as the lowest bit.
import fs from 'node:fs';

export default async function (core, args = []) {
  const at = args.indexOf('--joint');
  if (at >= 0) {
    const file = args[at + 1];
    if (!file || file.startsWith('--')) throw new Error('--joint needs a JSON file: --joint FILE.json');
    let query;
    try {
      query = JSON.parse(fs.readFileSync(file, 'utf8'));
    } catch (e) {
      throw new Error(`--joint ${file}: ${e.message}`);
    }
    try {
      return { __only: core.jointAnswer(query) };
    } catch (e) {
      throw new Error(`--joint ${file}: ${e.message ?? e}`);
    }
  }
  const a = core.jointAnswer(core.chapterTwoCellQuery());
  // The collinear preset (the chapter's exercise): A at 1 m and B at 2 m on
  // the beam axis, reading 2.0 m; its table as the page shows it.
  const c = core.jointPosterior(core.twoCellPreset('collinear'));
  return {
    twoCellCollinear: {
      cells: core.twoCellPreset('collinear').cells,
      joint: c.joint,
      marginals: c.marginals,
      bothOccupiedTrue: c.allOccupiedTrue,
      bothOccupiedFactored: c.allOccupiedFactored,
      bothFreeTrue: c.allFreeTrue,
      bothFreeFactored: c.allFreeFactored,
    },
    twoCell: {
      joint: a.joint,
      marginals: a.marginals,
      bothFreeTrue: a.allFreeTrue,
      bothFreeFactored: a.allFreeFactored,
    },
  };
}

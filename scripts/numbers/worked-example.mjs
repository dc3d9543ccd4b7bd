// The chapter's worked example: inverse model 0.7 / 0.3, prior 0.5,
// readings occupied, occupied, free.
export default async function (core) {
  const t = core.workedExample();
  return {
    workedExample: {
      lOcc: t.lOcc,
      lFree: t.lFree,
      steps: t.steps.map((s) => ({ l: s.l, p: s.p })),
    },
  };
}

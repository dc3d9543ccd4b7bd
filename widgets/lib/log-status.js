// The real-log panel's status line: what the core's session state says is
// under way, in words. Every figure is the core's (`state()`); a refusal of
// a pose source for what its poses would cost ends with the core's own
// advice (what fits), which a coarser resolution would not change.

const count = (n) => Number(n).toLocaleString('en-US');

/**
 * The core's advice when it refuses a pose source for what finding the poses
 * would cost (the last clause of its message: what fits), or `null` for any
 * other refusal.
 */
const poseAdvice = (error) => (/^(?:invalid poses: .*; ([^;]*)\)|the pose source .* passed its bound .*; ([^;]*))$/s.exec(error ?? '') ?? []).slice(1).find(Boolean) ?? null;

/** The status line for session state `state` of the log `name`; `null` to leave it as it is. */
export function statusText(state, name) {
  const main = state.panes[0];
  const read = state.read;
  if (state.state === 'reading') return `Reading ${name}: ${count(read?.records ?? 0)} ${read?.recordName ?? 'records'}, ${count(read?.scans ?? 0)} scans…`;
  if (state.state === 'planning') return 'Planning the maps at the new settings…';
  const advice = poseAdvice(state.error);
  if (state.state === 'awaiting-settings') {
    return advice
      ? `${name} is read; its poses would cost too much to find: ${advice}.`
      : `${name} is read; choose a coarser resolution or a shorter z_max to map it.`;
  }
  if (state.state === 'failed') {
    if (state.failed !== 'build') return `Could not read ${name}.`;
    return advice ? `The map stopped short: its poses cost more than their bound: ${advice}.` : 'The map stopped short: choose a coarser resolution.';
  }
  if (state.state === 'building' && main) return `Mapping: scan ${count(main.scansDone)} of ${count(main.scansTarget)}…`;
  return null;
}

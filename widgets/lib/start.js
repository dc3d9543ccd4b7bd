// A widget element's start-up, written once for every widget: its controls
// built in a turn of its own, the chapter core loaded and its constants
// taken in another, and the widget's first run made when it first nears
// the screen, in a third. Each step waits for a turn (widgets/lib/ui.js,
// startTurn): the page's widgets start one step per task, so the page
// paints and answers input in between, rather than all of them starting in
// the one task that loads their modules.
import { loadCore } from './core.js';
import { firstConnection, urlState } from './state.js';
import { showError, startTurn, whenVisible } from './ui.js';

/**
 * Starts `element` (a custom element whose attributes `spec` describes):
 * - `build()`: reads the attributes (`element.attrs`) and builds the
 *   controls, before the core has loaded;
 * - `withCore(constants)`: once `element.core` and `element.memory` are
 *   the core's, takes its `constants()` (bounds, defaults, names); an
 *   error there or in loading is shown as the core failing to load, and
 *   the widget goes no further;
 * - `whenSeen()`: the first run, when the element first comes into view
 *   (with `ahead`, a screen before, so a reader scrolling down waits for
 *   no widget).
 * - `landing(keys)`: the part of the widget a link's keys are about (the
 *   element itself when absent or null); see `landLink`.
 * Resolves once the start is arranged; does nothing when the element was
 * built already (moved in the document) or is no longer connected.
 */
export async function startWidget(element, spec, { build, withCore, whenSeen, ahead = false, landing = null }) {
  await startTurn();
  if (!element.isConnected || !firstConnection(element, spec)) return;
  // What the page wrote inside the element is its fallback, shown while no
  // widget runs: a host that sends no CORS header loads no module at all,
  // so no code of ours could say why (README, "A course page on another
  // origin"). The widget replaces it.
  element.replaceChildren();
  build();
  landLink(element, landing);
  try {
    ({ core: element.core, memory: element.memory } = await loadCore());
    await startTurn();
    withCore(element.core.constants());
  } catch (e) {
    showError(element, e, 'could not load the core: ');
    return;
  }
  whenVisible(element, async () => {
    await startTurn();
    await whenSeen();
  }, { ahead });
}

/**
 * A link that sets this widget's attributes and points at its section
 * (`?map-weaver.scans=300#map-weaver`, the exercises' links) lands on the
 * widget, not on the section's prose above it: the widget (or the part
 * `landing(keys)` names) is put at the top of the window once the page has
 * loaded (the browser's own scroll to the fragment comes at load), and so
 * starts at once, being on screen. A fragment alone (a table of contents)
 * keeps the browser's scroll to the section's heading.
 */
function landLink(element, landing) {
  const id = decodeURIComponent(location.hash.slice(1));
  if (!id) return;
  const keys = urlState(element);
  if (keys.size === 0) return;
  const named = document.getElementById(id);
  if (!named || !(named === element || named.contains(element))) return;
  const land = () => (landing?.(keys) ?? element).scrollIntoView({ block: 'start' });
  if (document.readyState === 'complete') land();
  else window.addEventListener('load', () => setTimeout(land, 0), { once: true });
}

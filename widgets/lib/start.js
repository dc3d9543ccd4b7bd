// A widget element's start-up, written once for every widget: its controls
// built in a turn of its own, the chapter core loaded and its constants
// taken in another, and the widget's first run made when it first nears
// the screen, in a third. Each step waits for a turn (widgets/lib/ui.js,
// startTurn): the page's widgets start one step per task, so the page
// paints and answers input in between, rather than all of them starting in
// the one task that loads their modules.
import { loadCore } from './core.js';
import { firstConnection } from './state.js';
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
 * Resolves once the start is arranged; does nothing when the element was
 * built already (moved in the document) or is no longer connected.
 */
export async function startWidget(element, spec, { build, withCore, whenSeen, ahead = false }) {
  await startTurn();
  if (!element.isConnected || !firstConnection(element, spec)) return;
  build();
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

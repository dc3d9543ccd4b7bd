// The real-log panel's maps on a narrow screen, and the legend of their
// colours. Side by side on a phone, three maps were thumbnails about 80 px
// wide, eleven cells to a screen pixel; so below NARROW_WIDTH the panel
// shows one map at a time at the panel's whole width, with a row of
// buttons naming each map (its caption) to switch between them. Every map
// is still drawn (switching shows it at once), only one is displayed.
import { el } from './ui.js';

/** Below this panel width (CSS pixels), one map at a time. */
export const NARROW_WIDTH = 600;

/**
 * The switcher: `update(captions, narrow)` makes one button per map and
 * shows the row when `narrow` and there is more than one map; `shown` is
 * the index of the map displayed; `onPick(k)` after a button press.
 */
export function paneSwitcher(onPick) {
  const root = el('div', { class: 'occgrid-controls map-weaver-log-switch', role: 'group', 'aria-label': 'map shown', hidden: true });
  const switcher = {
    root,
    shown: 0,
    update(captions, narrow) {
      root.hidden = !narrow || captions.length < 2;
      if (switcher.shown >= captions.length) switcher.shown = 0;
      const names = captions.map(shortName);
      if (root.childElementCount !== names.length || names.some((n, k) => root.children[k].textContent !== n)) {
        root.replaceChildren(...names.map((n, k) => {
          const b = el('button', { type: 'button', dataset: { pane: String(k) } }, n);
          b.addEventListener('click', () => {
            switcher.shown = k;
            switcher.mark();
            onPick(k);
          });
          return b;
        }));
      }
      switcher.mark();
    },
    mark() {
      [...root.children].forEach((b, k) => b.setAttribute('aria-pressed', String(k === switcher.shown)));
    },
  };
  return switcher;
}

/** A map's caption cut to its first clause: the button's name. */
function shortName(caption) {
  const text = String(caption || 'map');
  const cut = text.search(/[:(·,]/);
  return (cut > 0 ? text.slice(0, cut) : text).trim();
}

/** The colours of the maps, on screen (the canvas's label says them to a screen reader). */
export function mapLegend() {
  const key = (cls, text) => el('span', { class: 'map-weaver-log-key' }, el('span', { class: `map-weaver-log-swatch ${cls}`, 'aria-hidden': 'true' }), text);
  return el('p', { class: 'occgrid-caption map-weaver-log-legend', 'aria-hidden': 'true' },
    key('map-weaver-log-unknown', 'unknown'), key('map-weaver-log-free', 'free'), key('map-weaver-log-occupied', 'occupied'),
    key('map-weaver-log-path', 'the laser’s path and the robot'));
}

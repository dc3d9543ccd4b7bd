// A widget's state in the page URL, so that an instructor can hand out a
// link that opens a widget just so. The state is the widget's attributes
// (widgets/lib/attributes.js): the widget reports its current settings as
// attribute values, they go into the query string under the widget's key
// (`?map-weaver.seed=3&map-weaver.left-clamp=4`), and on load the widget
// sets them as its attributes before it reads them (only the attributes
// the widget declares: never event handlers or `style`). The key is the
// element's id, or its tag name without "occgrid-" (with "-2", "-3", … for
// further elements of the same tag), so several widgets share one URL.
import { el, button, ensureStyles } from './ui.js';
import { AttributeReader, MAX_JSON_TEXT } from './attributes.js';

/** The widget's key in the URL: its id, else its tag (numbered when repeated). */
export function widgetKey(host) {
  if (host.id) return host.id;
  const base = host.localName.replace(/^occgrid-/, '');
  const peers = [...document.getElementsByTagName(host.localName)].filter((e) => !e.id);
  const k = peers.indexOf(host);
  return k > 0 ? `${base}-${k + 1}` : base;
}

/**
 * The longest value of a link that is decoded, characters as the link
 * writes them: three for each character of the longest attribute value
 * (widgets/lib/attributes.js, MAX_JSON_TEXT), every one percent-encoded.
 * A longer one is over every attribute's cap however it decodes, and is
 * set as the link writes it, to be refused on its length: decoding a
 * megabyte of query (`URLSearchParams` over the whole URL) holds the page
 * for a third of a second.
 */
export const MAX_LINK_VALUE = 3 * MAX_JSON_TEXT;

/** One `name=value` piece of a query, decoded as `URLSearchParams` decodes it. */
const decodePart = (text) => (/[%+]/.test(text) ? new URLSearchParams(`a=${text}`).get('a') : text);

/**
 * The attribute values the page URL holds for `host`, as a Map from name
 * to text (a Map, so that a name such as `__proto__` is just a name).
 * Each `&`-separated piece is decoded alone, and a value longer than
 * `MAX_LINK_VALUE` not at all, so that nothing decodes a megabyte.
 */
export function urlState(host, search = location.search) {
  const prefix = `${widgetKey(host)}.`;
  const out = new Map();
  const query = search.startsWith('?') ? search.slice(1) : search;
  for (let start = 0; start < query.length;) {
    let end = query.indexOf('&', start);
    if (end < 0) end = query.length;
    const eq = query.indexOf('=', start);
    const keyEnd = eq < 0 || eq > end ? end : eq;
    // A key longer than the longest value a link decodes is no attribute's.
    if (keyEnd > start && keyEnd - start <= MAX_LINK_VALUE) {
      const key = decodePart(query.slice(start, keyEnd));
      if (key.startsWith(prefix)) {
        const raw = keyEnd < end ? query.slice(keyEnd + 1, end) : '';
        out.set(key.slice(prefix.length), raw.length > MAX_LINK_VALUE ? raw : decodePart(raw));
      }
    }
    start = end + 1;
  }
  return out;
}

/**
 * Sets `host`'s attributes from the page URL, if it holds any for this
 * widget: each value replaces only the attribute it names, so that a
 * course page's own attributes (`left-clamp="4" autoplay="off"`) survive a
 * link that names another one. The page's own values are kept in
 * `host.pageAttributes` (see `linkFor`).
 * Call once, before the widget first reads its attributes.
 *
 * Only the attributes the widget declares in `spec` are set. A link is
 * text anyone can write, and a page without a Content-Security-Policy
 * runs an `on*` attribute as script; `style`, `id` or `class` would let a
 * link restyle or re-key the element. Any other name is skipped with a
 * console warning naming it, not an error: a link made before an
 * attribute was renamed still opens the page.
 */
export function restoreFromUrl(host, spec) {
  host.pageAttributes = new Map(Object.keys(spec).filter((n) => host.hasAttribute(n)).map((n) => [n, host.getAttribute(n)]));
  const state = urlState(host);
  if (!state.size) return false;
  const key = widgetKey(host);
  for (const [name, value] of state) {
    if (!Object.hasOwn(spec, name)) {
      console.warn(`${host.localName}: ignored "${key}.${name}" in the page URL: a link may set only this widget's attributes (${Object.keys(spec).join(', ')})`);
      continue;
    }
    host.setAttribute(name, value);
  }
  return true;
}

/**
 * A widget element's first connection: the attributes a shared link
 * carries are set first, the stylesheet is loaded and `host.attrs` reads
 * the attributes of `spec`. False when the element was built already
 * (moving it in the document connects it again).
 */
export function firstConnection(host, spec) {
  if (host.built) return false;
  restoreFromUrl(host, spec);
  host.built = true;
  ensureStyles();
  host.attrs = new AttributeReader(host, spec);
  return true;
}

/**
 * The page URL with `host`'s state in it. `state` maps attribute names to
 * values; a value equal to the attribute's default (in `spec`), null or
 * undefined is left out, unless the page gave the element another value
 * for it: a link's keys replace only the attributes they name, so a
 * default that differs from the page's own attribute must be named. The fragment points at the widget (its id, or
 * the nearest enclosing element with an id) so the link opens there.
 */
export function linkFor(host, spec, state) {
  const url = new URL(location.href);
  const key = widgetKey(host);
  for (const k of [...url.searchParams.keys()]) if (k.startsWith(`${key}.`)) url.searchParams.delete(k);
  for (const [name, value] of Object.entries(state)) {
    if (value === null || value === undefined) continue;
    const text = String(value);
    // A default is left out, unless the page gave the element another
    // value (which the link must then override).
    const page = host.pageAttributes?.get(name);
    if (spec[name] && spec[name].default === text && (page === undefined || page === text)) continue;
    url.searchParams.set(`${key}.${name}`, text);
  }
  const anchor = host.id || host.parentElement?.closest('[id]')?.id;
  if (anchor) url.hash = anchor;
  return url.href;
}

/**
 * The "Copy link" control (control group "link"): puts the widget's
 * current state (`getState()` → attribute values) into the page URL and
 * copies the link; where the clipboard is not available (a page not
 * served over https, a denied permission) it shows the link selected in a
 * text box instead. The last link is also in `host.dataset.link`.
 * `copiedText()`, when given, says what the link keeps once it is copied.
 */
export function copyLinkControl(host, spec, getState, copiedText = null) {
  const status = el('output', { class: 'occgrid-link-status', 'aria-live': 'polite' });
  const field = el('input', {
    type: 'text', readonly: true, class: 'occgrid-link-field', hidden: true,
    'aria-label': 'Link to this widget with its current settings',
  });
  const copy = button('Copy link', async () => {
    let href;
    try {
      href = linkFor(host, spec, getState());
    } catch (e) {
      status.textContent = `No link: ${e && e.message ? e.message : e}`;
      return;
    }
    host.dataset.link = href;
    try {
      history.replaceState(history.state, '', href);
    } catch {
      // A sandboxed frame may not change its URL; the link is still shown.
    }
    field.value = href;
    try {
      await navigator.clipboard.writeText(href);
      field.hidden = true;
      status.textContent = copiedText?.() ?? 'Link copied: it opens this page with this widget as it is now.';
    } catch {
      field.hidden = false;
      field.focus();
      field.select();
      status.textContent = 'Copy this link (Ctrl+C or ⌘C):';
    }
  }, { name: 'copy-link', title: 'Copy a link that opens this page with this widget’s current settings' });
  copy.setAttribute('aria-label', `Copy link to this ${host.localName.replace(/^occgrid-/, '').replace(/-/g, ' ')} with its current settings`);
  return el('div', { class: 'occgrid-link', dataset: { controls: 'link' } }, copy, status, field);
}

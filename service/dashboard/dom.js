// Small DOM helpers shared by the dashboard's modules: element lookup,
// element creation that never parses markup, number formatting, file
// download.

/** The element with this id. */
export const $ = (id) => document.getElementById(id);

/** Creates an element; string children become text, never markup (plugin and controller text is untrusted). */
export function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (k === "class") e.className = v;
    else if (k === "dataset") Object.assign(e.dataset, v);
    else e[k] = v;
  }
  e.append(...children.filter((c) => c !== null && c !== undefined && c !== false));
  return e;
}

/** A number with `d` decimals, or – when it is not a finite number. */
export const fmt = (v, d = 3) => (typeof v === "number" && isFinite(v) ? v.toFixed(d) : "–");

/** Offers `text` as a file download named `name`. */
export function download(name, type, text) {
  const a = el("a", { href: URL.createObjectURL(new Blob([text], { type })), download: name });
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

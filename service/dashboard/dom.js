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

/**
 * The API's sentences mark names with backticks (`s`, `0..7`): as nodes,
 * each marked part a <code> element, the rest text, never markup. An
 * unpaired backtick stays as it is.
 */
export function textWithCode(text) {
  const parts = String(text ?? "").split("`");
  if (parts.length % 2 === 0) parts.splice(-2, 2, `${parts.at(-2)}\`${parts.at(-1)}`);
  return parts.map((p, i) => (i % 2 ? el("code", {}, p) : p)).filter((p) => p !== "");
}

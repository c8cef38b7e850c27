// The jog panel's parts that need no API: the arm configuration (Status
// and Turn) in words, the axis bars against the software limits, and the
// joint rows (A1–A6: step buttons around a limit bar). The wiring to the
// API is in app.js.
import { el, fmt } from "./dom.js";

const DEG = Math.PI / 180;

/** φ: the A3 angle (degrees) at which the arm is stretched, from the OPW lengths; Status bit 1 is set for A3 ≥ φ. */
export function elbowAngle(model) {
  const o = model?.opw_mm;
  return o ? Math.atan2(Math.abs(o.a2), o.c3) / DEG : null;
}

/**
 * Status bits in words, as the simulator and the service use them
 * (docs/DASHBOARD.md): bit 0 = the wrist point at negative X of the A1
 * frame (overhead area), bit 1 = A3 ≥ φ (elbow up), bit 2 = A5 < 0 (wrist
 * flipped).
 */
export function statusWords(s, model) {
  const phi = elbowAngle(model);
  const at = phi === null ? "φ" : `${fmt(phi, 1)}°`;
  return [
    s & 1 ? "overhead area" : "basic area",
    s & 2 ? `elbow up (A3 ≥ ${at})` : `elbow down (A3 < ${at})`,
    s & 4 ? "wrist flipped (A5 < 0)" : "wrist not flipped (A5 ≥ 0)",
  ].join(" · ");
}

/** Turn bits in words: bit n set = axis n+1 negative. */
export function turnWords(t) {
  const negative = [1, 2, 3, 4, 5, 6].filter((i) => t & (1 << (i - 1))).map((i) => `A${i}`);
  if (!negative.length) return "all axes ≥ 0";
  if (negative.length === 6) return "all axes < 0";
  return `${negative.join(", ")} < 0, the others ≥ 0`;
}

/** Status in a few words (the pose table). */
export function statusShort(s) {
  return [s & 1 ? "overhead" : "basic", s & 2 ? "elbow up" : "elbow down", s & 4 ? "wrist flipped" : "wrist not flipped"].join(" · ");
}

/** A bar between the limits [lo, hi] with a line at 0° and a marker (see placeMark). */
export function axisBar(lo, hi) {
  const zero = el("span", { class: "zero" });
  zero.style.left = `${(-lo / (hi - lo)) * 100}%`;
  return el("span", { class: "bar" }, zero, el("span", { class: "mark" }));
}

/** Puts the bar's marker at `v`; true when within 5 % of a limit. */
export function placeMark(bar, v, lo, hi) {
  bar.querySelector(".mark").style.left = `${Math.max(0, Math.min(100, ((v - lo) / (hi - lo)) * 100))}%`;
  return Math.min(v - lo, hi - v) < 0.05 * (hi - lo);
}

/** Builds the joint rows (A1–A6: −, the bar, +, the value) into `box`, once. */
export function buildJoints(box, limits) {
  if (box.children.length || !limits) return;
  for (let i = 0; i < 6; i++) {
    const [lo, hi] = limits[i];
    const name = `a${i + 1}`;
    box.append(
      el(
        "div",
        { class: "joint", dataset: { axis: name } },
        el("b", {}, `A${i + 1}`),
        el("button", { type: "button", dataset: { joint: `${name},-1` }, title: `A${i + 1} − one step (PTP)` }, "−"),
        axisBar(lo, hi),
        el("button", { type: "button", dataset: { joint: `${name},1` }, title: `A${i + 1} + one step (PTP)` }, "+"),
        el("span", { class: "value" }, "–"),
        el("small", {}, `${lo}…${hi}°`),
      ),
    );
  }
}

/**
 * Updates the joint rows: values, bars, and which step buttons work.
 * `why` = why driving is off (role, control), or null; a step that would
 * pass a software limit is off too, saying so.
 */
export function showJoints(box, axes, limits, step, why) {
  if (!limits || !box.children.length) return;
  const values = axes ? [axes.a1, axes.a2, axes.a3, axes.a4, axes.a5, axes.a6] : [];
  [...box.children].forEach((row, i) => {
    const [lo, hi] = limits[i];
    const v = values[i];
    const known = typeof v === "number";
    row.querySelector(".value").textContent = known ? `${fmt(v, 2)}°` : "–";
    if (known) row.classList.toggle("near", placeMark(row.querySelector(".bar"), v, lo, hi));
    row.title = known ? `A${i + 1} ${fmt(v)}° within [${lo}°, ${hi}°]` : "";
    for (const b of row.querySelectorAll("button")) {
      const sign = Number(b.dataset.joint.split(",")[1]);
      const to = known ? v + sign * step : null;
      const limit = sign > 0 ? hi : lo;
      const past = known && (sign > 0 ? to > hi : to < lo);
      const off = why || (!known ? "the axis angles are not known yet" : past ? `A${i + 1} ${sign > 0 ? "+" : "−"} ${step}° would pass the software limit ${limit}°` : null);
      b.disabled = !!off;
      b.title = off || `A${i + 1} ${sign > 0 ? "+" : "−"} ${step}° to ${fmt(to, 2)}° (PTP)`;
    }
  });
}

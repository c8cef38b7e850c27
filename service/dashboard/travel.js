// Pen-up travel: which motions of a batch draw and which only move the
// tool between strokes. The views draw travel faint and dashed, so a
// drawing shows its strokes, not the moves between them.
//
// The rule (docs/DASHBOARD.md, "Drawing and travel"): the drawing plane of
// a batch is the lowest Z (base frame) among the start and end points of
// its path motions (LIN, CIRC, SLIN, SCIRC, SPL). A motion is travel when it
// is a PTP (Cartesian, axis-specific or SPTP), or a path motion whose start, end or (CIRC)
// auxiliary point lies more than PLANE_TOL_MM above that plane. A batch
// without path motions has no drawing plane: all of it is travel. The
// first motion starts where the robot was when the plan arrived (unknown
// for a plan read from the history: then only its end and auxiliary point
// count). Plain functions, no DOM.

/** How far above the drawing plane a point may be and still be on it (mm). */
export const PLANE_TOL_MM = 0.5;

const isCp = (m) => ["lin", "circ", "slin", "scirc", "spl"].includes(m.type);

/**
 * Classifies the motions of a plan (`plan.motions` of a `plan` event):
 * `start` = [x, y, z] where the batch starts (or null), `endOf(m)` = the
 * end point of a motion (or null). Returns {motions: [{type, start, end,
 * aux}], plane (mm or null), travel: [bool per motion]}.
 */
export function classifyPlan(motions, start, endOf) {
  const out = [];
  let at = start;
  for (const m of motions) {
    // An I/O action or a dwell (no target) does not move the robot: the
    // next motion starts where the previous one ended.
    const action = ["set_output", "wait_input", "dwell"].includes(m.type);
    const end = action ? null : endOf(m);
    out.push({ type: m.type, start: at, end, aux: m.aux || null });
    if (!action) at = end;
  }
  const zs = out
    .filter(isCp)
    .flatMap((m) => [m.start, m.end])
    .filter(Boolean)
    .map((p) => p[2]);
  const plane = zs.length ? Math.min(...zs) : null;
  const above = (p) => !!p && plane !== null && p[2] > plane + PLANE_TOL_MM;
  const travel = out.map((m) => !isCp(m) || above(m.start) || above(m.end) || above(m.aux));
  return { motions: out, plane, travel };
}

/**
 * Whether an executed sample {cid, motion, pose} is travel, from the
 * classified plans by command id (`kinds`: cid → {plane, travel}). A sample
 * without a motion index (a real controller's positions) is travel when it
 * is above its batch's drawing plane; a sample of no known plan (a KRL
 * program run) is drawn as a stroke.
 */
export function sampleIsTravel(kinds, s) {
  const k = kinds.get(s.cid);
  if (!k) return false;
  if (Number.isInteger(s.motion) && s.motion < k.travel.length) return k.travel[s.motion];
  return k.plane === null || s.pose[2] > k.plane + PLANE_TOL_MM;
}

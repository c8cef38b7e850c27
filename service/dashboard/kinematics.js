// Forward kinematics of the configured robot model for drawing, in KUKA
// conventions (mm, degrees; frames as X Y Z A B C with A about Z, B about
// Y, C about X): the stick model's joint points from the OPW lengths of
// GET /api/v1/model and the axis angles of GET /api/v1/state, and the
// circle through three points for planned CIRC motions. Plain math, no
// three.js, so it runs anywhere (also in Node for checks).

const DEG = Math.PI / 180;

/** 4×4 row-major matrix product a·b. */
export function mul(a, b) {
  const out = new Array(16).fill(0);
  for (let r = 0; r < 4; r++)
    for (let c = 0; c < 4; c++)
      for (let k = 0; k < 4; k++) out[r * 4 + c] += a[r * 4 + k] * b[k * 4 + c];
  return out;
}

const translate = (x, y, z) => [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1];
function rotZ(t) {
  const c = Math.cos(t), s = Math.sin(t);
  return [c, -s, 0, 0, s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
}
function rotY(t) {
  const c = Math.cos(t), s = Math.sin(t);
  return [c, 0, s, 0, 0, 1, 0, 0, -s, 0, c, 0, 0, 0, 0, 1];
}
function rotX(t) {
  const c = Math.cos(t), s = Math.sin(t);
  return [1, 0, 0, 0, 0, c, -s, 0, 0, s, c, 0, 0, 0, 0, 1];
}

/** The matrix of a KUKA frame [x, y, z, a, b, c]: translation · Rz(A) · Ry(B) · Rx(C). */
export function frameMatrix([x, y, z, a, b, c]) {
  return mul(translate(x, y, z), mul(rotZ(a * DEG), mul(rotY(b * DEG), rotX(c * DEG))));
}

/** Inverse of a rigid transform. */
export function invert(m) {
  // R^T and -R^T·p
  const r = [m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]];
  const p = [m[3], m[7], m[11]];
  const t = [0, 1, 2].map((i) => -(r[i * 3] * p[0] + r[i * 3 + 1] * p[1] + r[i * 3 + 2] * p[2]));
  return [r[0], r[1], r[2], t[0], r[3], r[4], r[5], t[1], r[6], r[7], r[8], t[2], 0, 0, 0, 1];
}

/** Position [x, y, z] of a matrix. */
export const origin = (m) => [m[3], m[7], m[11]];

/** Transforms the point p by m. */
export function apply(m, [x, y, z]) {
  return [0, 1, 2].map((r) => m[r * 4] * x + m[r * 4 + 1] * y + m[r * 4 + 2] * z + m[r * 4 + 3]);
}

/** KUKA frame [x, y, z, a, b, c] of a matrix (B in [−90°, 90°]). */
export function matrixFrame(m) {
  const b = Math.asin(Math.max(-1, Math.min(1, -m[8])));
  let a, c;
  if (Math.abs(Math.cos(b)) > 1e-9) {
    a = Math.atan2(m[4], m[0]);
    c = Math.atan2(m[9], m[10]);
  } else {
    a = Math.atan2(-m[1], m[5]);
    c = 0;
  }
  return [m[3], m[7], m[11], a / DEG, b / DEG, c / DEG];
}

/**
 * The arm's joints for axis angles A1..A6 (degrees) in the robot root frame:
 * `points` = floor, top of the column, A2, A3, forearm offset, wrist point,
 * flange centre; `flange` = the flange frame's matrix (Z out of the flange
 * face). The chain is the one `GET /api/v1/model` documents.
 */
export function skeleton(model, axes) {
  const { a1, a2, b, c1, c2, c3, c4 } = model.opw_mm;
  const q = axes.map((v) => v * DEG);
  const points = [[0, 0, 0]];
  let t = rotZ(-q[0]);
  points.push(origin(mul(t, translate(0, 0, c1))));
  t = mul(t, translate(a1, b, c1));
  points.push(origin(t));
  t = mul(mul(t, rotY(q[1] + Math.PI / 2)), translate(0, 0, c2));
  points.push(origin(t));
  t = mul(mul(t, rotY(q[2])), translate(a2, 0, 0));
  points.push(origin(t));
  t = mul(t, translate(0, 0, c3));
  points.push(origin(t));
  t = mul(mul(mul(t, rotZ(-q[3])), rotY(q[4])), rotZ(-q[5]));
  const flange = mul(t, translate(0, 0, c4));
  points.push(origin(flange));
  return { points, flange };
}

/** TCP pose in the base frame for these axes: inv(base) · flange · tool (as the service computes it). */
export function tcpInBase(model, axes, tool, base) {
  const { flange } = skeleton(model, axes);
  return matrixFrame(mul(invert(frameMatrix(base)), mul(flange, frameMatrix(tool))));
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (a, k) => [a[0] * k, a[1] * k, a[2] * k];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];

/**
 * Points along the arc from `start` through `aux` to `end` (a CIRC), or
 * the straight segment when the three are collinear.
 */
/**
 * Points of one segment of a spline block, from `start` to `end` (both
 * included): the centripetal Catmull-Rom curve the simulated controllers
 * follow (krl/kinematics `catmull_rom`), with `before` (the previous
 * point of the block, or null) and `after` (the next one, or null) as its
 * neighbours; a missing neighbour is mirrored.
 */
export function splineSegment(start, end, before, after, steps = 16) {
  const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  if (dist(start, end) < 1e-6) return [start, end];
  const mirror = (p, q) => [2 * p[0] - q[0], 2 * p[1] - q[1], 2 * p[2] - q[2]];
  const c = [
    before && dist(before, start) >= 1e-6 ? before : mirror(start, end),
    start,
    end,
    after && dist(after, end) >= 1e-6 ? after : mirror(end, start),
  ];
  const knot = (a, b) => Math.max(Math.sqrt(dist(a, b)), 1e-9);
  const t1 = knot(c[0], c[1]);
  const t2 = t1 + knot(c[1], c[2]);
  const t3 = t2 + knot(c[2], c[3]);
  const lerp = (p, q, ta, tb, u) => {
    const w = (u - ta) / (tb - ta);
    return [p[0] + (q[0] - p[0]) * w, p[1] + (q[1] - p[1]) * w, p[2] + (q[2] - p[2]) * w];
  };
  const out = [];
  for (let i = 0; i <= steps; i++) {
    const u = t1 + ((t2 - t1) * i) / steps;
    const a1 = lerp(c[0], c[1], 0, t1, u);
    const a2 = lerp(c[1], c[2], t1, t2, u);
    const a3 = lerp(c[2], c[3], t2, t3, u);
    const b1 = lerp(a1, a2, 0, t2, u);
    const b2 = lerp(a2, a3, t1, t3, u);
    out.push(lerp(b1, b2, t1, t2, u));
  }
  return out;
}

export function arc(start, aux, end, steps = 48) {
  const u = sub(aux, start), v = sub(end, start);
  const n = cross(u, v);
  const nn = dot(n, n);
  if (nn < 1e-9) return [start, end];
  const centre = add(start, scale(add(scale(cross(v, n), dot(u, u)), scale(cross(n, u), dot(v, v))), 1 / (2 * nn)));
  const e1 = sub(start, centre);
  const r = Math.sqrt(dot(e1, e1));
  const x = scale(e1, 1 / r);
  const y = scale(cross(n, x), 1 / Math.sqrt(nn));
  const angle = (p) => {
    const d = sub(p, centre);
    const t = Math.atan2(dot(d, y), dot(d, x));
    return t < 0 ? t + 2 * Math.PI : t;
  };
  // Going the positive way about n passes aux before end by construction.
  const sweep = angle(end) || 2 * Math.PI;
  const out = [];
  for (let i = 0; i <= steps; i++) {
    const t = (sweep * i) / steps;
    out.push(add(centre, add(scale(x, r * Math.cos(t)), scale(y, r * Math.sin(t)))));
  }
  return out;
}

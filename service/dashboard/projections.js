// Top (X up, Y to the left: as seen standing in front of the robot) and
// side (X–Z) projections of the TCP path on 2D canvases:
// executed path (strokes solid, pen-up travel faint and dashed: see
// travel.js), planned paths and the current TCP, equal scale on both
// axes, fitted to what is shown. Also the SVG export of the same view.

const EXECUTED = "#1f6feb";
const PLANNED = "#f08c00";
/** Opacity of travel (pen up) lines. */
const FAINT = 0.35;

/**
 * Splits a path into runs of the same kind: `travel[i]` says whether the
 * segment ending at points[i] is travel. Each run starts at the last point
 * of the one before, so the runs join. [{points, travel}]
 */
export function runs(points, travel = []) {
  const out = [];
  for (let i = 0; i + 1 < points.length; ) {
    const kind = !!travel[i + 1];
    let j = i + 1;
    while (j + 1 < points.length && !!travel[j + 1] === kind) j++;
    out.push({ points: points.slice(i, j + 1), travel: kind });
    i = j;
  }
  return out;
}

/**
 * One projection: `u`, `v` = indices into [x, y, z] for the horizontal and
 * vertical axis; `flipU` draws the horizontal axis growing to the left.
 */
export class Projection {
  constructor(canvas, u, v, label, flipU = false) {
    this.canvas = canvas;
    this.u = u;
    this.v = v;
    this.su = flipU ? -1 : 1;
    this.label = label;
    new ResizeObserver(() => this.draw(this.last || {})).observe(canvas);
  }

  /** The view box: [minU, minV, size] covering every point, with a margin. */
  bounds(executed, planned, tcp, zones) {
    let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    const take = (p) => {
      const u = this.su * p[this.u];
      lo = [Math.min(lo[0], u), Math.min(lo[1], p[this.v])];
      hi = [Math.max(hi[0], u), Math.max(hi[1], p[this.v])];
    };
    for (let i = 0; i < executed.length; i++) take(executed[i]);
    planned.forEach((plan) => plan.points.forEach(take));
    if (tcp) take(tcp);
    // Keep-out zones are near the work: in view (the workspace box may be
    // much larger and is drawn clipped).
    for (const k of zones?.keep_out || []) {
      take([k.x[0], k.y[0], k.z[0]]);
      take([k.x[1], k.y[1], k.z[1]]);
    }
    if (!isFinite(lo[0])) return null;
    const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], 20) * 1.15;
    return [(lo[0] + hi[0] - size) / 2, (lo[1] + hi[1] - size) / 2, size];
  }

  /**
   * Redraws: `executed` = [[x, y, z], ...] with `travel` = [bool, ...] (the
   * segment to point i is travel), `planned` = [{points, travel}], `tcp` = [x, y, z].
   */
  draw({ executed = [], travel = [], planned = [], tcp = null, zones = null }) {
    this.last = { executed, travel, planned, tcp, zones };
    const c = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = c.clientWidth, h = c.clientHeight;
    if (!w || !h) return;
    if (c.width !== Math.round(w * dpr)) c.width = Math.round(w * dpr);
    if (c.height !== Math.round(h * dpr)) c.height = Math.round(h * dpr);
    // CPU-backed (willReadFrequently): long polylines rasterise faster there than on
    // software GL, and the tests read the pixels back.
    const g = c.getContext("2d", { willReadFrequently: true });
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, w, h);
    g.fillStyle = "#5b6470";
    g.font = "12px system-ui, sans-serif";
    g.fillText(this.label, 6, 14);
    const box = this.bounds(executed, planned, tcp, zones);
    this.toCanvas = null;
    if (!box) return;
    const [u0, v0, size] = box;
    const k = Math.min(w, h) / size;
    const ox = (w - size * k) / 2, oy = (h - size * k) / 2;
    const X = (p) => ox + (this.su * p[this.u] - u0) * k;
    const Y = (p) => h - oy - (p[this.v] - v0) * k;
    /** A base-frame point → canvas pixels (device pixels, as getImageData counts them). */
    this.toCanvas = (p) => [X(p) * dpr, Y(p) * dpr];
    // scale bar
    const step = niceStep(size / 4);
    g.strokeStyle = "#5b6470";
    g.beginPath();
    g.moveTo(6, h - 8);
    g.lineTo(6 + step * k, h - 8);
    g.stroke();
    g.fillText(`${step} mm`, 10 + step * k, h - 4);
    const line = (pts, colour, dash, alpha, width) => {
      if (pts.length < 2) return;
      g.strokeStyle = colour;
      g.globalAlpha = alpha;
      g.setLineDash(dash);
      g.lineWidth = width;
      g.beginPath();
      g.moveTo(X(pts[0]), Y(pts[0]));
      for (let i = 1; i < pts.length; i++) g.lineTo(X(pts[i]), Y(pts[i]));
      g.stroke();
      g.setLineDash([]);
      g.globalAlpha = 1;
    };
    // The workspace box (dashed), keep-out zones (red) and the floor (side
    // view): where the path may not go. `zoneShapes` lists what was drawn,
    // in canvas pixels (for the tests).
    this.zoneShapes = [];
    if (zones) {
      const rect = (r, kind, name) => {
        const p0 = [r.x[0], r.y[0], r.z[0]], p1 = [r.x[1], r.y[1], r.z[1]];
        const x0 = Math.min(X(p0), X(p1)), x1 = Math.max(X(p0), X(p1));
        const y0 = Math.min(Y(p0), Y(p1)), y1 = Math.max(Y(p0), Y(p1));
        if (kind === "keep_out") {
          g.fillStyle = "rgba(217, 45, 32, 0.18)";
          g.fillRect(x0, y0, x1 - x0, y1 - y0);
          g.strokeStyle = "#d92d20";
          g.setLineDash([]);
        } else {
          g.strokeStyle = "#2e7d32";
          g.setLineDash([8, 4]);
        }
        g.lineWidth = 1.5;
        g.strokeRect(x0, y0, x1 - x0, y1 - y0);
        g.setLineDash([]);
        if (name) {
          g.fillStyle = "#d92d20";
          g.fillText(name, x0 + 3, y0 + 13);
        }
        this.zoneShapes.push({ kind, name: name || null, x0: x0 * dpr, y0: y0 * dpr, x1: x1 * dpr, y1: y1 * dpr });
      };
      if (zones.box) rect(zones.box, "box", null);
      for (const k of zones.keep_out || []) rect(k, "keep_out", k.name);
      if (zones.floor_z !== null && zones.floor_z !== undefined && this.v === 2) {
        const y = Y([0, 0, zones.floor_z]);
        g.strokeStyle = "#8d6e63";
        g.lineWidth = 2;
        g.beginPath();
        g.moveTo(0, y);
        g.lineTo(w, y);
        g.stroke();
        g.fillStyle = "#8d6e63";
        g.fillText(`floor z ${zones.floor_z}`, 6, y - 4);
        this.zoneShapes.push({ kind: "floor", name: null, x0: 0, y0: y * dpr, x1: w * dpr, y1: y * dpr });
      }
    }
    for (const plan of planned) {
      for (const r of runs(plan.points, plan.travel)) line(r.points, PLANNED, r.travel ? [3, 5] : [6, 4], r.travel ? FAINT : 1, 1.5);
    }
    for (const r of runs(executed, travel)) line(r.points, EXECUTED, r.travel ? [4, 4] : [], r.travel ? FAINT : 1, r.travel ? 1.2 : 1.5);
    if (tcp) {
      g.fillStyle = "#d92d20";
      g.beginPath();
      g.arc(X(tcp), Y(tcp), 4, 0, 2 * Math.PI);
      g.fill();
    }
  }

  /** The same drawing as an SVG document (mm units, Y up): strokes solid, travel faint and dashed. */
  svg({ executed = [], travel = [], planned = [] }) {
    const box = this.bounds(executed, planned, null) || [0, 0, 100];
    const [u0, v0, size] = box;
    const pts = (list) => list.map((p) => `${(this.su * p[this.u] - u0).toFixed(3)},${(size - (p[this.v] - v0)).toFixed(3)}`).join(" ");
    const faint = `stroke-opacity="${FAINT}"`;
    const lines = planned
      .flatMap((p) => runs(p.points, p.travel))
      .map((r) => `<polyline class="planned${r.travel ? " travel" : ""}" fill="none" stroke="${PLANNED}" stroke-dasharray="${r.travel ? "1.5 2.5" : "6 4"}" ${r.travel ? faint : ""} stroke-width="0.8" points="${pts(r.points)}"/>`)
      .concat(
        runs(executed, travel).map((r) =>
          r.travel
            ? `<polyline class="executed travel" fill="none" stroke="${EXECUTED}" stroke-dasharray="2 2" ${faint} stroke-width="0.6" points="${pts(r.points)}"/>`
            : `<polyline class="executed" fill="none" stroke="${EXECUTED}" stroke-width="0.8" points="${pts(r.points)}"/>`,
        ),
      );
    return (
      `<?xml version="1.0" encoding="UTF-8"?>\n` +
      `<svg xmlns="http://www.w3.org/2000/svg" width="${size.toFixed(1)}mm" height="${size.toFixed(1)}mm" viewBox="0 0 ${size.toFixed(3)} ${size.toFixed(3)}">\n` +
      `<title>kuka-bridge TCP path, ${this.label}; lower left corner at ${"XYZ"[this.u]} = ${(this.su * u0).toFixed(3)} mm, ${"XYZ"[this.v]} = ${v0.toFixed(3)} mm; travel (pen up) dashed</title>\n` +
      lines.join("\n") +
      "\n</svg>\n"
    );
  }
}

function niceStep(x) {
  const p = 10 ** Math.floor(Math.log10(x));
  const m = x / p;
  return (m >= 5 ? 5 : m >= 2 ? 2 : 1) * p;
}

// Top (X up, Y to the left: as seen standing in front of the robot) and
// side (X–Z) projections of the TCP path on 2D canvases:
// executed path, planned paths and the current TCP, equal scale on both
// axes, fitted to what is shown. Also the SVG export of the same view.

const EXECUTED = "#1f6feb";
const PLANNED = "#f08c00";

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
  bounds(executed, planned, tcp) {
    let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    const take = (p) => {
      const u = this.su * p[this.u];
      lo = [Math.min(lo[0], u), Math.min(lo[1], p[this.v])];
      hi = [Math.max(hi[0], u), Math.max(hi[1], p[this.v])];
    };
    for (let i = 0; i < executed.length; i++) take(executed[i]);
    planned.forEach((line) => line.forEach(take));
    if (tcp) take(tcp);
    if (!isFinite(lo[0])) return null;
    const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], 20) * 1.15;
    return [(lo[0] + hi[0] - size) / 2, (lo[1] + hi[1] - size) / 2, size];
  }

  /** Redraws: `executed` = [[x, y, z], ...], `planned` = list of such lists, `tcp` = [x, y, z]. */
  draw({ executed = [], planned = [], tcp = null }) {
    this.last = { executed, planned, tcp };
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
    const box = this.bounds(executed, planned, tcp);
    if (!box) return;
    const [u0, v0, size] = box;
    const k = Math.min(w, h) / size;
    const ox = (w - size * k) / 2, oy = (h - size * k) / 2;
    const X = (p) => ox + (this.su * p[this.u] - u0) * k;
    const Y = (p) => h - oy - (p[this.v] - v0) * k;
    // scale bar
    const step = niceStep(size / 4);
    g.strokeStyle = "#5b6470";
    g.beginPath();
    g.moveTo(6, h - 8);
    g.lineTo(6 + step * k, h - 8);
    g.stroke();
    g.fillText(`${step} mm`, 10 + step * k, h - 4);
    const line = (pts, colour, dash) => {
      if (pts.length < 2) return;
      g.strokeStyle = colour;
      g.setLineDash(dash);
      g.lineWidth = 1.5;
      g.beginPath();
      g.moveTo(X(pts[0]), Y(pts[0]));
      for (let i = 1; i < pts.length; i++) g.lineTo(X(pts[i]), Y(pts[i]));
      g.stroke();
      g.setLineDash([]);
    };
    planned.forEach((p) => line(p, PLANNED, [6, 4]));
    line(executed, EXECUTED, []);
    if (tcp) {
      g.fillStyle = "#d92d20";
      g.beginPath();
      g.arc(X(tcp), Y(tcp), 4, 0, 2 * Math.PI);
      g.fill();
    }
  }

  /** The same drawing as an SVG document (mm units, Y up). */
  svg({ executed = [], planned = [] }) {
    const box = this.bounds(executed, planned, null) || [0, 0, 100];
    const [u0, v0, size] = box;
    const pts = (list) => list.map((p) => `${(this.su * p[this.u] - u0).toFixed(3)},${(size - (p[this.v] - v0)).toFixed(3)}`).join(" ");
    const lines = planned
      .map((p) => `<polyline fill="none" stroke="${PLANNED}" stroke-dasharray="6 4" stroke-width="0.8" points="${pts(p)}"/>`)
      .concat([`<polyline fill="none" stroke="${EXECUTED}" stroke-width="0.8" points="${pts(executed)}"/>`]);
    return (
      `<?xml version="1.0" encoding="UTF-8"?>\n` +
      `<svg xmlns="http://www.w3.org/2000/svg" width="${size.toFixed(1)}mm" height="${size.toFixed(1)}mm" viewBox="0 0 ${size.toFixed(3)} ${size.toFixed(3)}">\n` +
      `<title>kuka-bridge TCP path, ${this.label}; lower left corner at ${"XYZ"[this.u]} = ${(this.su * u0).toFixed(3)} mm, ${"XYZ"[this.v]} = ${v0.toFixed(3)} mm</title>\n` +
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

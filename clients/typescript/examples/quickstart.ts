/**
 * Drive a robot through kuka-bridge from TypeScript.
 *
 *     npm run build && node dist/examples/quickstart.js [BASE_URL] [PLUGIN_WASM]
 *
 * BASE_URL defaults to http://127.0.0.1:8080 (`kuka-bridge run --simulate`);
 * KB_TOKEN, if set, is the bearer token; PLUGIN_WASM, if given, is installed
 * as the plugin `draw-circle` and called.
 */
import { readFileSync } from "node:fs";
import { callPlugin, connect, type MotionRequest, ok, ProblemError } from "../src/index.js";

const baseUrl = process.argv[2] ?? "http://127.0.0.1:8080";
const token = process.env.KB_TOKEN;
const api = connect(baseUrl, token);

const ptp = (x: number, y: number, z: number): MotionRequest => ({ type: "ptp", target: { x, y, z } });
const lin = (x: number, y: number, z: number): MotionRequest => ({ type: "lin", target: { x, y, z }, velocity_m_s: 0.2 });
const circ = (aux: [number, number, number], to: [number, number, number]): MotionRequest => ({
  type: "circ",
  aux: { x: aux[0], y: aux[1], z: aux[2] },
  target: { x: to[0], y: to[1], z: to[2] },
  velocity_m_s: 0.2,
});

function smiley(cx: number, cy: number, z: number, up = 20): MotionRequest[] {
  const r = 40;
  return [
    ptp(cx + r, cy, z + up), lin(cx + r, cy, z),
    circ([cx, cy + r, z], [cx - r, cy, z]), circ([cx, cy - r, z], [cx + r, cy, z]), lin(cx + r, cy, z + up),
    ptp(cx + 12, cy + 15, z + up), lin(cx + 12, cy + 15, z), lin(cx + 12, cy + 15, z + up),
    ptp(cx + 12, cy - 15, z + up), lin(cx + 12, cy - 15, z), lin(cx + 12, cy - 15, z + up),
    ptp(cx - 10, cy + 20, z + up), lin(cx - 10, cy + 20, z),
    circ([cx - 22, cy, z], [cx - 10, cy - 20, z]), lin(cx - 10, cy - 20, z + up),
  ];
}

async function main(): Promise<number> {
  // 1. Read the state.
  const state = ok(await api.GET("/api/v1/state"));
  console.log(`connection ${state.connection}, position ${JSON.stringify(state.position)}`);

  // 2. PTP, LIN and CIRC, one request each.
  ok(await api.POST("/api/v1/home"));
  const here = ok(await api.GET("/api/v1/state")).position;
  if (!here) throw new Error("position unknown");
  const [x, y, z] = [here.x, here.y, here.z - 100];
  for (const motion of [ptp(x - 60, y, z), lin(x - 60, y + 40, z), circ([x - 20, y + 80, z], [x + 20, y + 40, z])]) {
    const job = ok(await api.POST("/api/v1/motions", { body: { motions: [motion] } }));
    console.log(`${motion.type}: job ${job.id} ${job.state}`);
  }

  // 3. The smiley as one batch without waiting; the job is polled to its end.
  let job = ok(await api.POST("/api/v1/motions", { body: { motions: smiley(x - 40, y, z - 50), wait: false } }));
  while (!["done", "failed", "cancelled"].includes(job.state)) {
    await new Promise((r) => setTimeout(r, 100));
    job = ok(await api.GET("/api/v1/jobs/{id}", { params: { path: { id: job.id } } }));
  }
  console.log(`smiley: job ${job.id} ${job.state}, ${job.completed}/${job.motions} motions`);
  if (job.state !== "done") return 1;

  // 4. An unreachable target is a typed error with a stable code.
  try {
    ok(await api.POST("/api/v1/motions", { body: { motions: [ptp(5000, 0, 0)] } }));
    console.log("an unreachable target was accepted");
    return 1;
  } catch (e) {
    if (!(e instanceof ProblemError)) throw e;
    console.log(`refused as expected: ${e.problem.code} (${e.problem.detail})`);
  }

  // 5. A plugin installed from its bytes, then called.
  const wasmPath = process.argv[3];
  if (wasmPath) {
    const info = ok(
      await api.PUT("/api/v1/plugins/{name}", {
        params: { path: { name: "draw-circle" } },
        body: readFileSync(wasmPath) as unknown as string,
        bodySerializer: (b) => b as unknown as BodyInit,
        headers: { "content-type": "application/wasm" },
      }),
    );
    console.log(`installed ${info.name} ${info.version}`);
    const done = (await callPlugin(baseUrl, "draw-circle", "/circle", { x: x - 40, y, z: z - 50, radius: 30 }, token)) as { completed: number };
    console.log(`plugin drew ${done.completed} motions`);
    try {
      await callPlugin(baseUrl, "draw-circle", "/circle", { x: 5000, y: 0, z: 0, radius: 30 }, token);
      console.log("an unreachable circle was accepted");
      return 1;
    } catch (e) {
      if (!(e instanceof ProblemError)) throw e;
      console.log(`plugin refused as expected: ${e.problem.code}`);
    }
  }
  return 0;
}

main().then((code) => process.exit(code), (e) => { console.error(e); process.exit(1); });

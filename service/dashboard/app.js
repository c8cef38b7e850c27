// kuka-bridge dashboard: wires the panels to the public API only —
// GET /api/v1/state, /api/v1/model, /api/v1/control, /openapi.json, the
// recent events /api/v1/events/recent and the event stream /api/v1/events
// (state, job, plan, alarm; continued from the last event id seen), the
// simulator's trace when simulating, and the same POST/PUT calls any client makes —
// with this tab's token when access control is on. Updates are pushed by
// the event stream; nothing polls in a tight loop.
import { ArmView } from "./arm.js";
import { Projection } from "./projections.js";
import { arc, splineSegment, tcpInBase } from "./kinematics.js";
import { $, el, fmt, download, textWithCode } from "./dom.js";
import { renderPlugins } from "./plugins.js";
import { classifyPlan, sampleIsTravel } from "./travel.js";
import { axisBar, buildJoints, placeMark, showJoints, statusShort, statusWords, turnWords } from "./jog.js";

const MAX_PATH = 100000; // executed samples kept (oldest dropped)
const MAX_EVENTS = 500;
const HISTORY = 200; // recent events shown after a (re)load
const MAX_KINDS = 500; // classified plans kept (by command id)
const RANK = { viewer: 1, operator: 2, admin: 3 };

/** Everything the page knows; also `window.dashboard` for tests and the curious. */
const state = {
  token: sessionStorage.getItem("kb-token") || "",
  ready: false,
  robot: null,
  model: null,
  you: null,
  doc: null,
  jobs: new Map(),
  mine: new Set(), // jobs this page started: their outcome is reported

  plans: new Map(),
  kinds: new Map(), // cid → {plane, travel[]}: which motions of a batch are pen-up travel
  path: [],
  traceSince: null,
  traceSeen: new Set(),
  events: [],
  lastEventId: null, // the newest job/plan/alarm event id seen: the stream continues from it
  seenIds: new Set(),
};
window.dashboard = state;

// ---------------------------------------------------------------- API

function headers(json) {
  const h = state.token ? { Authorization: `Bearer ${state.token}` } : {};
  if (json) h["Content-Type"] = "application/json";
  return h;
}

/** Calls the API; returns {ok, status, body}. Failures are reported on the page. */
async function api(method, path, body) {
  let r;
  try {
    r = await fetch(path, { method, headers: headers(body !== undefined), body: body === undefined ? undefined : JSON.stringify(body) });
  } catch (e) {
    say(`${method} ${path}: ${e.message}`);
    if (method !== "GET") logEvent("refused", `${method} ${path}: the service cannot be reached (${e.message})`);
    return { ok: false, status: 0, body: null };
  }
  const text = await r.text();
  let parsed = null;
  try {
    parsed = text ? JSON.parse(text) : null;
  } catch {
    parsed = text;
  }
  const out = { ok: r.ok, status: r.status, body: parsed };
  if (!r.ok && method !== "GET") {
    const why = parsed && parsed.code ? `${parsed.code}: ${parsed.detail}` : `HTTP ${r.status}`;
    say(`${method} ${path} refused — ${why}`);
    logEvent("refused", `${method} ${path} → ${why}`);
  }
  return out;
}
state.api = api;

/** A short message at the bottom of the page; it goes away after 8 s. */
function say(text) {
  $("message").replaceChildren(...textWithCode(text));
  clearTimeout(state.sayTimer);
  if (text) state.sayTimer = setTimeout(() => ($("message").textContent = ""), 8000);
}

// ---------------------------------------------------------------- state

/** Takes a state (from an event or GET): data at once, drawing once per frame. */
function showState(s) {
  const before = state.robot;
  state.robot = s;
  const p = s.position;
  const moved = !before || JSON.stringify(before.axes) !== JSON.stringify(s.axes) || before.busy !== s.busy || before.controller.last_cid !== s.controller.last_cid;
  if (moved) {
    if (state.traceApi) fetchTrace();
    else if (p) addPositions([{ t: Date.now() / 1000, cid: s.controller.last_cid, motion: null, pose: [p.x, p.y, p.z, p.a, p.b, p.c] }], true);
  }
  if (!before || before.connection !== s.connection || before.busy !== s.busy || before.controller.status !== s.controller.status || before.controller.error?.code !== s.controller.error?.code) {
    logEvent("state", `${s.connection} ${s.busy ? "busy" : s.controller.status}${s.controller.error ? ` — ${s.controller.error.code}` : ""}${p ? ` at X ${fmt(p.x, 1)} Y ${fmt(p.y, 1)} Z ${fmt(p.z, 1)}` : ""}`);
  }
  if (state.statePending) return;
  state.statePending = true;
  requestAnimationFrame(() => {
    state.statePending = false;
    renderState(state.robot);
  });
}

function renderState(s) {
  const c = $("connection");
  const reachable = !state.streamDown;
  c.textContent = reachable ? s.connection : "no service";
  c.className = `pill ${reachable ? s.connection : "offline"}`;
  document.body.classList.toggle("stale", !reachable || s.connection !== "online");
  const sim = $("simulated");
  sim.textContent = s.controller.simulated ? "simulated" : "real controller";
  sim.className = `pill ${s.controller.simulated ? "sim" : "real"}`;
  sim.hidden = false;
  const st = $("status");
  st.textContent = s.busy ? "busy" : s.controller.status;
  st.className = `pill ${s.controller.error ? "error" : s.busy ? "busy" : ""}`;
  $("mode").textContent = s.controller.mode;
  const saf = s.controller.safety;
  $("safety").hidden = !saf;
  if (saf) {
    const problems = [saf.emergency_stop && "EMERGENCY STOP", !saf.drives_ready && "drives off", !saf.user_safety && "operator safety open", saf.stop_message && "stop message"].filter(Boolean);
    $("safety").textContent = problems.length ? problems.join(" · ") : `drives on · program ${saf.program}`;
    $("safety").className = `pill ${problems.length ? "error" : ""}`;
  }
  $("override").textContent = `${fmt(s.speed.override_pct, 0)} %`;
  if (document.activeElement !== $("override-input")) {
    $("override-input").value = s.speed.override_pct;
    $("override-value").textContent = fmt(s.speed.override_pct, 0);
  }
  const err = s.controller.error;
  $("reset").hidden = !err;
  state.condition = state.authLost
    ? "The token was rejected or revoked: paste another below."
    : !reachable
      ? `No connection to the kuka-bridge service since ${state.streamDown.toLocaleTimeString()} — reconnecting; the values shown are from then.`
      : err
        ? `Controller error — ${err.code}: ${err.detail}`
        : s.connection === "locked"
          ? "The command file is locked by another process (channel_locked)."
          : s.connection !== "online"
            ? "No heartbeat from the controller (controller_offline)."
            : null;
  renderAlarm();
  const p = s.position;
  const rows = [["X", "x", "mm"], ["Y", "y", "mm"], ["Z", "z", "mm"], ["A", "a", "°"], ["B", "b", "°"], ["C", "c", "°"], ["S", "s", ""], ["T", "t", ""]];
  const body = $("pose").tBodies[0];
  if (!body.rows.length) {
    for (const [label, , unit] of rows) body.append(el("tr", {}, el("th", {}, label), el("td"), el("td", {}, unit)));
  }
  rows.forEach(([, key], i) => {
    const v = p?.[key];
    body.rows[i].cells[1].textContent = v === undefined ? "–" : key === "s" ? `${v} (${v.toString(2).padStart(3, "0")}b)` : key === "t" ? `${v} (${v.toString(2).padStart(6, "0")}b)` : fmt(v);
    if (key === "s" || key === "t") {
      const words = v === undefined ? "" : key === "s" ? statusShort(v) : turnWords(v);
      if (body.rows[i].cells[2].textContent !== words) body.rows[i].cells[2].replaceChildren(el("small", {}, words));
      body.rows[i].title = v === undefined ? "" : key === "s" ? `Status ${v}: ${statusWords(v, state.model)}` : `Turn ${v}: ${turnWords(v)}`;
    }
  });
  showAxes(s.axes);
  showConfigWords();
  showRunning();
  renderIo(s.io);
  renderAnalog(s.analog);
  // The 3D view and the projections only when the arm or its frames moved.
  const pose = JSON.stringify([s.axes, s.tool, s.base]);
  if (state.model && s.axes && pose !== state.drawnPose) {
    state.drawnPose = pose;
    const a = s.axes;
    state.view.setPose(state.model, [a.a1, a.a2, a.a3, a.a4, a.a5, a.a6], frame(s.tool), frame(s.base));
    drawPath();
  }
}

/** A notice in the red bar for `ms` (a failed job of this page, an alarm, a Stop that did not go through). */
function showAlarm(text, ms = 15000) {
  state.notice = { text, until: Date.now() + ms };
  renderAlarm();
  setTimeout(renderAlarm, ms + 50);
}

/** The red bar: the standing condition (from the state) and the latest notice while it lasts. */
function renderAlarm() {
  const notice = state.notice && Date.now() < state.notice.until ? state.notice.text : null;
  const parts = [notice, state.condition].filter(Boolean);
  $("alarm").replaceChildren(...textWithCode(parts.join(" · ")));
  $("alarm-bar").hidden = !parts.length;
}

const frame = (f) => (f ? [f.x, f.y, f.z, f.a, f.b, f.c] : [0, 0, 0, 0, 0, 0]);

/** A1–A6 against their software limits (rows built once, then updated in place), here and in the jog panel. */
function showAxes(axes) {
  const box = $("axes");
  const limits = state.model?.limits_deg;
  if (!axes) return;
  if (!box.children.length) {
    for (let i = 0; i < 6; i++) {
      const row = el("div", { class: "axis" });
      row.append(el("b", {}, `A${i + 1}`), el("span", { class: "value" }));
      if (limits) row.append(axisBar(...limits[i]), el("small", {}, `${limits[i][0]}…${limits[i][1]}`));
      box.append(row);
    }
  }
  [axes.a1, axes.a2, axes.a3, axes.a4, axes.a5, axes.a6].forEach((v, i) => {
    const row = box.children[i];
    row.querySelector(".value").textContent = `${fmt(v)}°`;
    if (!limits) return;
    const [lo, hi] = limits[i];
    row.classList.toggle("near", placeMark(row.querySelector(".bar"), v, lo, hi));
    row.title = `A${i + 1} ${fmt(v)}° within [${lo}°, ${hi}°]`;
  });
  showJointRows();
}

/** The jog panel's joint rows: values, bars, and which steps are possible. */
function showJointRows() {
  const limits = state.model?.limits_deg;
  buildJoints($("joints"), limits);
  showJoints($("joints"), state.robot?.axes, limits, Number($("rot-step").value), blocked("POST /api/v1/motions"));
}

/** The S and T fields' configuration in words: the typed value, or the current one that an empty field keeps. */
function showConfigWords() {
  const f = $("goto").elements;
  const p = state.robot?.position;
  const ptp = $("jog-type").value === "ptp";
  const word = (input, max, words, empty) => {
    const text = input.value.trim();
    if (!ptp) return ["S and T apply to PTP only (a LIN keeps the configuration)", false];
    if (text === "") return [empty, false];
    const v = Number(text);
    if (!Number.isInteger(v) || v < 0 || v > max) return [`must be a whole number from 0 to ${max}`, true];
    return [words(v), false];
  };
  const keep = $("config-mode").value === "keep";
  const emptyS = !keep
    ? "empty: the bridge chooses (reachable, clear of singularities, least axis travel)"
    : p
      ? `empty: keeps S ${p.s} (${statusWords(p.s, state.model)})`
      : "empty: keeps the current Status";
  const [sw, sbad] = word(f.s, 7, (v) => `S ${v}: ${statusWords(v, state.model)}`, emptyS);
  const [tw, tbad] = word(f.t, 63, (v) => `T ${v}: ${turnWords(v)}`, !keep && f.s.value.trim() === "" ? "empty: chosen with the Status" : "empty: the shortest axis motion");
  for (const [id, text, bad] of [["s-words", sw, sbad], ["t-words", tw, tbad]]) {
    if ($(id).textContent !== text) $(id).textContent = text;
    $(id).classList.toggle("bad", bad);
  }
}

// ---------------------------------------------------------------- path

/** Adds executed samples {t, cid, motion, pose}; `dedupe` skips a repeat of the last pose. */
function addPositions(samples, dedupe) {
  const fresh = [];
  for (const s of samples) {
    const last = state.path[state.path.length - 1];
    if (dedupe && last && Math.hypot(last.pose[0] - s.pose[0], last.pose[1] - s.pose[1], last.pose[2] - s.pose[2]) < 0.01) continue;
    s.travel = sampleIsTravel(state.kinds, s);
    state.path.push(s);
    fresh.push(s);
  }
  if (state.path.length > MAX_PATH) {
    state.path.splice(0, state.path.length - MAX_PATH / 2);
    redrawExecuted();
  } else if (fresh.length) {
    state.view.addExecuted(
      fresh.map((s) => s.pose),
      fresh.map((s) => s.travel),
    );
  }
  if (fresh.length) drawPath();
}

/** The whole executed path into the 3D view again (after a trim or a reclassification). */
function redrawExecuted() {
  state.view.setExecuted(
    state.path.map((s) => s.pose),
    state.path.map((s) => s.travel),
  );
}

/**
 * Remembers which motions of a batch are travel (by its command id); samples
 * of that batch already on the page (a plan read from the history after a
 * reload) are classified again.
 */
function rememberKinds(cid, kinds) {
  state.kinds.set(cid, kinds);
  if (state.kinds.size > MAX_KINDS) state.kinds.delete(state.kinds.keys().next().value);
  let changed = false;
  for (const s of state.path) {
    if (s.cid !== cid) continue;
    const travel = sampleIsTravel(state.kinds, s);
    changed ||= travel !== s.travel;
    s.travel = travel;
  }
  if (changed) {
    redrawExecuted();
    drawPath();
  }
}

/** Whether each sample of the page's path is travel (tests). */
state.pathTravel = () => state.path.map((s) => !!s.travel);

/** Fetches the simulator's trace since the last sample seen; one request at a time, re-run if asked meanwhile. */
async function fetchTrace() {
  if (state.traceBusy) {
    state.traceAgain = true;
    return;
  }
  state.traceBusy = true;
  try {
    do {
      state.traceAgain = false;
      const since = state.traceSince === null ? "" : `?since=${state.traceSince - 1e-6}`;
      const r = await api("GET", `/api/v1/sim/trace${since}`);
      if (!r.ok || !Array.isArray(r.body)) break;
      const fresh = r.body.filter((s) => !state.traceSeen.has(`${s.t}/${s.cid}/${s.motion}`));
      if (fresh.length) {
        const lastT = fresh[fresh.length - 1].t;
        if (lastT !== state.traceSince) state.traceSeen.clear();
        for (const s of fresh) if (s.t === lastT) state.traceSeen.add(`${s.t}/${s.cid}/${s.motion}`);
        state.traceSince = lastT;
        addPositions(fresh, false);
      }
    } while (state.traceAgain);
  } finally {
    state.traceBusy = false;
  }
}

/**
 * A plan's path and kinds: `points` (CIRCs as arcs, spline blocks as their
 * curves), `travel[i]` = the
 * segment to points[i] is travel, the drawing plane and the travel flag of
 * each motion (travel.js). `start` = where the batch starts, or null (a plan
 * from the history).
 */
function planOf(plan, start) {
  const endOf = (m) => {
    if (m.target) return m.target.slice(0, 3);
    if (m.axes && state.model && state.robot) return tcpInBase(state.model, m.axes, frame(state.robot.tool), frame(state.robot.base)).slice(0, 3);
    return null;
  };
  const k = classifyPlan(plan.motions, start, endOf);
  const points = [];
  const travel = [];
  k.motions.forEach((m, i) => {
    if (!m.end) return;
    if (!points.length && m.start) {
      points.push(m.start);
      travel.push(false);
    }
    const prev = plan.motions[i - 1];
    const inBlock = prev && prev.type === "spl" && prev.left > 1;
    const after = m.type === "spl" && plan.motions[i].left > 1 ? k.motions[i + 1]?.end : null;
    const pts =
      (m.type === "circ" || m.type === "scirc") && m.start && m.aux
        ? arc(m.start, m.aux, m.end).slice(1)
        : m.type === "spl" && m.start
          ? splineSegment(m.start, m.end, inBlock ? k.motions[i - 1].start : null, after).slice(1)
          : [m.end];
    for (const p of pts) {
      points.push(p);
      travel.push(k.travel[i]);
    }
  });
  return { job: plan.job, cid: plan.cid, points, travel, kinds: { plane: k.plane, travel: k.travel } };
}

/** Where a new plan starts: where the previous unfinished plan ends, else at the robot. */
function planStart(plan) {
  const earlier = [...state.plans.values()].filter((p) => p.job < plan.job);
  const p = state.robot?.position;
  return earlier.length ? earlier[earlier.length - 1].points.at(-1) : p ? [p.x, p.y, p.z] : null;
}

function showPlans() {
  state.view.setPlanned([...state.plans.values()]);
  drawPath();
}

/** Draws the projections at the next frame (coalesces many updates). */
function drawPath() {
  if (state.drawPending) return;
  state.drawPending = true;
  requestAnimationFrame(() => {
    state.drawPending = false;
    drawPathNow();
  });
}

function drawPathNow() {
  const executed = state.path.map((s) => s.pose);
  const travel = state.path.map((s) => s.travel);
  const planned = [...state.plans.values()];
  const p = state.robot?.position;
  const tcp = p ? [p.x, p.y, p.z] : null;
  const zones = state.zones;
  state.top.draw({ executed, travel, planned, tcp, zones });
  state.side.draw({ executed, travel, planned, tcp, zones });
  $("path-count").textContent = `${state.path.length} points`;
}
state.drawPathNow = drawPathNow;

/** The executed path as CSV (what Export CSV downloads). */
function pathCsv() {
  const rows = state.path.map((s) => [s.t.toFixed(3), s.cid ?? "", s.motion ?? "", ...s.pose.map((v) => v.toFixed(3))].join(","));
  return ["t_s,cid,motion,x_mm,y_mm,z_mm,a_deg,b_deg,c_deg", ...rows].join("\n") + "\n";
}
state.pathCsv = pathCsv;

// ---------------------------------------------------------------- jobs and events

/** Remembers a job this page started; reports it at once if its end already arrived. */
function track(id) {
  state.mine.add(id);
  const j = state.jobs.get(id);
  if (j) showJob(j);
}

function showJob(job) {
  state.jobs.set(job.id, job);
  if (state.mine.has(job.id) && ["done", "failed", "cancelled"].includes(job.state)) {
    state.mine.delete(job.id);
    if (job.error) {
      showAlarm(`Job #${job.id} (${job.operation}) ${job.state} — ${job.error.code}: ${job.error.detail}`);
      say(`job #${job.id} ${job.state}: ${job.error.code}`);
    } else {
      say(`job #${job.id} ${job.operation} done`);
    }
  }
  if (job.state === "done" || job.state === "failed" || job.state === "cancelled") {
    if (state.plans.delete(job.id)) showPlans();
  }
  if (state.jobs.size > 200) state.jobs.delete(Math.min(...state.jobs.keys()));
  renderJobs();
  if (state.traceApi) fetchTrace();
}

/** The job list and the running job, at the next frame. */
function renderJobs() {
  if (state.jobsPending) return;
  state.jobsPending = true;
  requestAnimationFrame(() => {
    state.jobsPending = false;
    const ids = [...state.jobs.keys()].sort((a, b) => b - a).slice(0, 20);
    $("jobs").replaceChildren(
      ...ids.map((id) => {
        const j = state.jobs.get(id);
        return el(
          "li",
          { class: j.state },
          el("b", {}, `#${id}`),
          ` ${j.operation}${j.motions ? ` (${j.motions})` : ""} `,
          el("span", { class: "state" }, j.state),
          " ",
          el("small", {}, j.origin || j.requested_by || ""),
          j.error && el("div", { class: "error" }, ...textWithCode(`${j.error.code}: ${j.error.detail}`)),
        );
      }),
    );
    showRunning();
  });
}

function showRunning() {
  const id = state.robot?.current_job;
  const j = id != null ? state.jobs.get(id) : null;
  const box = $("running");
  if (!j) {
    box.textContent = state.robot?.queue_length ? `${state.robot.queue_length} queued` : "no job running";
    return;
  }
  const pct = j.motions ? Math.round((100 * j.completed) / j.motions) : null;
  const bar = el("progress", { max: 100 });
  if (pct !== null) bar.value = pct;
  box.replaceChildren(el("b", {}, `#${j.id}`), ` ${j.operation} — ${j.state}${pct !== null ? ` — ${j.completed}/${j.motions} motions` : ""}`, bar);
}

function logEvent(type, text, at = new Date()) {
  state.events.push({ at, type, text });
  if (state.events.length > MAX_EVENTS) state.events.splice(0, state.events.length - MAX_EVENTS);
  showEvents();
}

function showEvents() {
  if (state.eventsPending) return;
  state.eventsPending = true;
  requestAnimationFrame(() => {
    state.eventsPending = false;
    const types = new Set([...$("event-filter").querySelectorAll("input[type=checkbox]:checked")].map((i) => i.value));
    types.add("refused");
    const needle = $("event-text").value.trim().toLowerCase();
    const shown = state.events.filter((e) => types.has(e.type) && (!needle || `${e.type} ${e.text}`.toLowerCase().includes(needle))).slice(-150).reverse();
    $("events").replaceChildren(
      ...shown.map((e) => {
        return el("li", { class: e.type }, el("time", {}, e.at.toLocaleTimeString()), " ", el("b", {}, e.type), " ", ...textWithCode(e.text));
      }),
    );
  });
}

/** The Events panel's line for a job, plan or alarm event. */
function eventText(type, d) {
  if (type === "job") return `#${d.id} ${d.operation} ${d.state}${d.motions ? ` ${d.completed}/${d.motions}` : ""}${d.error ? ` — ${d.error.code}: ${d.error.detail}` : ""}`;
  if (type === "plan") return `#${d.job} cid ${d.cid}: ${d.motions.map((m) => m.type).join(" ")}`;
  if (type === "io") return `${d.kind === "input" ? "$IN" : "$OUT"}[${d.index}]${d.name ? ` ${d.name}` : ""} ${d.value ? "on" : "off"}`;
  return `${d.code}: ${d.detail}`;
}

/** True the first time an event id is seen (a replay never shows an event twice); remembers the newest. */
function firstSeen(id) {
  if (id === null || id === undefined || id === "") return true;
  const n = Number(id);
  if (state.seenIds.has(n)) return false;
  state.seenIds.add(n);
  if (state.seenIds.size > 4 * MAX_EVENTS) state.seenIds.delete(state.seenIds.values().next().value);
  state.lastEventId = n;
  return true;
}

/**
 * The recent job, plan and alarm events (GET /api/v1/events/recent) into the
 * Events panel, and the plans' kinds for the path; the stream then
 * continues from the newest id. Jobs come from GET /api/v1/jobs.
 */
async function loadHistory() {
  const r = await api("GET", `/api/v1/events/recent?limit=${HISTORY}`);
  if (!r.ok || !Array.isArray(r.body)) return;
  for (const e of r.body) {
    if (!firstSeen(e.id)) continue;
    if (e.type === "plan") rememberKinds(e.data.cid, planOf(e.data, null).kinds);
    logEvent(e.type, eventText(e.type, e.data), new Date(e.at_ms));
  }
  // Nothing held yet: 0 asks the stream for every event held when it opens.
  if (state.lastEventId === null) state.lastEventId = 0;
}

function listen() {
  const q = new URLSearchParams();
  if (state.token) q.set("access_token", state.token);
  // The stream replays what came after the last event seen (a reconnecting
  // EventSource sends Last-Event-ID itself, which the service prefers).
  if (state.lastEventId !== null) q.set("last_event_id", state.lastEventId);
  const events = new EventSource(`/api/v1/events${q.size ? `?${q}` : ""}`);
  events.addEventListener("state", (e) => showState(JSON.parse(e.data)));
  events.addEventListener("io", (e) => {
    if (!firstSeen(e.lastEventId)) return;
    logEvent("io", eventText("io", JSON.parse(e.data)));
  });
  events.addEventListener("job", (e) => {
    if (!firstSeen(e.lastEventId)) return;
    const j = JSON.parse(e.data);
    showJob(j);
    logEvent("job", eventText("job", j));
  });
  events.addEventListener("plan", (e) => {
    if (!firstSeen(e.lastEventId)) return;
    const plan = JSON.parse(e.data);
    // A path publishes a plan per append (`first` > 0 after the first):
    // its pieces join into one drawn path.
    const prev = plan.first > 0 ? state.plans.get(plan.job) : undefined;
    const piece = planOf(plan, prev ? (prev.points.at(-1) ?? null) : planStart(plan));
    state.lastPlan = prev
      ? {
          ...prev,
          points: prev.points.concat(piece.points.slice(1)),
          travel: prev.travel.concat(piece.travel.slice(1)),
          kinds: { plane: prev.kinds.plane, travel: prev.kinds.travel.concat(piece.kinds.travel) },
        }
      : piece;
    rememberKinds(plan.cid, state.lastPlan.kinds);
    if (!["done", "failed", "cancelled"].includes(state.jobs.get(plan.job)?.state)) state.plans.set(plan.job, state.lastPlan);
    showPlans();
    logEvent("plan", eventText("plan", plan));
  });
  events.addEventListener("alarm", (e) => {
    if (!firstSeen(e.lastEventId)) return;
    const a = JSON.parse(e.data);
    logEvent("alarm", eventText("alarm", a));
    showAlarm(`${a.code}: ${a.detail}`, 10000);
  });
  events.addEventListener("lagged", (e) => logEvent("alarm", `missed ${e.data} events (page too slow, or no longer held by the service)`));
  events.onerror = async () => {
    // Lost service, or lost access? Ask once; a revoked token needs a new one, not patience.
    const r = await fetch("/api/v1/state", { headers: headers() }).catch(() => null);
    if (r && (r.status === 401 || r.status === 429)) {
      events.close();
      state.authLost = true;
      state.streamDown = null;
      $("role").textContent = "no access";
      $("auth").hidden = false;
      say("the token was rejected or revoked: paste another");
    } else if (!r || !r.ok) {
      state.streamDown = state.streamDown || new Date();
    }
    if (state.robot) renderState(state.robot);
    // A refused reconnection closes the stream for good: try again later.
    if (events.readyState === EventSource.CLOSED && !state.authLost) setTimeout(reconnect, 2000);
  };
  events.onopen = () => {
    if (state.streamDown) {
      state.streamDown = null;
      resync();
    }
  };
  state.stream = events;
}

// ---------------------------------------------------------------- roles and control

/** The role an operation ("METHOD /path template") needs, from /openapi.json. */
function requiredRole(op) {
  const [method, path] = op.split(" ");
  return state.doc?.paths?.[path]?.[method.toLowerCase()]?.["x-required-role"] || "admin";
}

function allowed(op) {
  return (RANK[state.you?.role] || 0) >= (RANK[requiredRole(op)] || 3);
}

/** Who else holds control, if anyone (then operations marked `x-needs-control` are refused). */
function heldBy() {
  const l = state.control?.lease;
  return l && l.holder !== state.you?.name ? l.holder : null;
}

function needsControl(op) {
  const [method, path] = op.split(" ");
  return !!state.doc?.paths?.[path]?.[method.toLowerCase()]?.["x-needs-control"];
}

/** Why this operation is not possible for this page now, or null. */
function blocked(op) {
  if (!allowed(op)) return `needs the ${requiredRole(op)} role (you are ${state.you?.role || "unknown"})`;
  if (needsControl(op) && heldBy()) return `${heldBy()} holds control of the robot`;
  return null;
}

/** The TCP in the base frame as the page's own kinematics put it (the drawn arm's tip). */
state.drawnTcp = () => {
  const s = state.robot;
  if (!state.model || !s?.axes) return null;
  const a = s.axes;
  return tcpInBase(state.model, [a.a1, a.a2, a.a3, a.a4, a.a5, a.a6], frame(s.tool), frame(s.base));
};

/** Disables what the caller's role may not do, saying which role it needs. */
function applyRole() {
  for (const node of document.querySelectorAll("[data-op]")) {
    if (node.tagName === "SECTION" || node.tagName === "FORM") continue;
    if (node.dataset.hint === undefined) node.dataset.hint = node.title; // its own explanation
    const why = blocked(node.dataset.op);
    node.disabled = !!why;
    node.title = why || node.dataset.hint;
  }
  for (const form of document.querySelectorAll("form[data-op]")) {
    const ok = !blocked(form.dataset.op);
    for (const i of form.querySelectorAll("input, select")) i.disabled = !ok;
  }
  const jog = blocked("POST /api/v1/motions");
  for (const i of $("goto").querySelectorAll("input, select, #fill-current")) i.disabled = !!jog;
  // S and T are PTP only.
  for (const k of ["s", "t"]) $("goto").elements[k].disabled = !!jog || $("jog-type").value !== "ptp";
  $("config-mode").disabled = !!jog || $("jog-type").value !== "ptp";
  $("step").disabled = !!jog;
  $("rot-step").disabled = !!jog;
  showJointRows();
  const auth = !!state.control?.auth;
  if (!auth) for (const b of [$("take-control"), $("release-control")]) b.disabled = true;
  $("logout").hidden = !auth;
  // Said on the page, not only in tooltips (touch screens show none).
  $("jog-note").textContent = jog ? `Driving is off: ${jog}.` : "";
  $("jog-note").hidden = !jog;
  const stop = blocked("POST /api/v1/stop");
  $("stop-note").textContent = stop ? `Stop ${stop}` : "";
  $("stop-note").hidden = !stop;
}

async function loadControl() {
  const r = await api("GET", "/api/v1/control");
  if (!r.ok) return;
  state.you = r.body.you;
  state.control = r.body;
  const l = r.body.lease;
  $("role").textContent = r.body.auth ? `${r.body.you.name} · ${r.body.you.role}` : "no auth (local)";
  $("control").textContent = !r.body.auth ? "control: not needed" : l ? `control: ${l.holder}${l.holder === r.body.you.name ? " (you)" : ""}` : "control: free";
  applyRole();
}

// ---------------------------------------------------------------- actions

function onClick(id, f) {
  $(id).addEventListener("click", (e) => {
    e.preventDefault();
    f().then(loadControl);
  });
}

async function move(motion) {
  const r = await api("POST", "/api/v1/motions", { motions: [motion], wait: false });
  if (r.ok) {
    say(`job #${r.body.id} queued`);
    track(r.body.id);
  }
  return r;
}
state.move = move;

$("stop").addEventListener("click", async () => {
  const r = await api("POST", "/api/v1/stop");
  if (r.ok) {
    say("stopped");
  } else {
    const why = r.body?.code ? `${r.body.code}: ${r.body.detail}` : r.status ? `HTTP ${r.status}` : "the service cannot be reached";
    showAlarm(`STOP DID NOT GO THROUGH — ${why}. Use the teach pendant's stop.`, 30000);
    logEvent("refused", `STOP did not go through — ${why}`);
  }
});

$("goto").addEventListener("submit", (e) => {
  e.preventDefault();
  const type = $("jog-type").value;
  const target = {};
  // S and T (whole numbers) only with a PTP: a LIN keeps the configuration.
  for (const k of type === "ptp" ? ["x", "y", "z", "a", "b", "c", "s", "t"] : ["x", "y", "z", "a", "b", "c"]) {
    const v = e.target.elements[k].value;
    if (v !== "") target[k] = Number(v);
  }
  const motion = { type, target };
  if (type === "ptp") motion.config = $("config-mode").value;
  move(motion).then(loadControl);
});

onClick("fill-current", async () => {
  const p = state.robot?.position;
  if (p) for (const k of ["x", "y", "z", "a", "b", "c"]) $("goto").elements[k].value = p[k].toFixed(3);
  if (p) for (const k of ["s", "t"]) $("goto").elements[k].value = p[k];
  showConfigWords();
});

$("jog-type").addEventListener("change", () => {
  applyRole();
  showConfigWords();
});
$("config-mode").addEventListener("change", showConfigWords);
for (const k of ["s", "t"]) $("goto").elements[k].addEventListener("input", showConfigWords);

// Cartesian steps: X/Y/Z by the mm step, A/B/C by the ° step, relative to the pose.
for (const b of document.querySelectorAll("[data-step]")) {
  b.addEventListener("click", () => {
    const [axis, sign] = b.dataset.step.split(",");
    const step = Number($("xyz".includes(axis) ? "step" : "rot-step").value);
    move({ type: $("jog-type").value, target: { [axis]: Number(sign) * step }, relative: true }).then(loadControl);
  });
}

// Joint steps: an axis-specific PTP by the ° step (the buttons are off where a step would pass a limit).
$("joints").addEventListener("click", (e) => {
  const b = e.target.closest("[data-joint]");
  if (!b || b.disabled) return;
  const [axis, sign] = b.dataset.joint.split(",");
  move({ type: "ptp_axes", axes: { [axis]: Number(sign) * Number($("rot-step").value) }, relative: true }).then(loadControl);
});
$("rot-step").addEventListener("change", showJointRows);

onClick("home", () => api("POST", "/api/v1/home"));
$("logout").addEventListener("click", () => {
  sessionStorage.removeItem("kb-token");
  location.reload();
});
onClick("reset", () => api("POST", "/api/v1/reset"));
onClick("take-control", () => api("POST", "/api/v1/control", {}));
onClick("release-control", () => api("DELETE", "/api/v1/control"));

$("override-input").addEventListener("input", () => ($("override-value").textContent = $("override-input").value));
$("override-input").addEventListener("change", () => api("PUT", "/api/v1/speed", { override_pct: Number($("override-input").value) }).then(loadControl));

$("clear-path").addEventListener("click", () => {
  state.path = [];
  state.plans.clear();
  state.view.setExecuted([]);
  showPlans();
});
$("export-csv").addEventListener("click", () => download("tcp-path.csv", "text/csv", pathCsv()));
/** The top view as SVG (what Export SVG downloads). */
state.pathSvg = () => state.top.svg({ executed: state.path.map((s) => s.pose), travel: state.path.map((s) => s.travel), planned: [...state.plans.values()] });
$("export-svg").addEventListener("click", () => download("tcp-path-top.svg", "image/svg+xml", state.pathSvg()));

for (const type of ["input", "change", "search"]) $("event-filter").addEventListener(type, showEvents);
$("refresh-plugins").addEventListener("click", () => loadDoc().then(loadPlugins));

$("upload").addEventListener("submit", async (e) => {
  e.preventDefault();
  const f = e.target.elements;
  const body = { name: f.name.value.trim(), src: await f.src.files[0].text() };
  if (f.dat.files[0]) body.dat = await f.dat.files[0].text();
  const r = await api("POST", "/api/v1/programs", body);
  if (r.ok) say(`program ${r.body.name} uploaded (entry ${r.body.entry})`);
  await loadPrograms();
});

async function loadPrograms() {
  const r = await api("GET", "/api/v1/programs");
  if (!r.ok) return;
  $("programs").replaceChildren(
    ...r.body.map((p) => {
      const li = el("li", {}, el("b", {}, p.name), " ", el("small", {}, `${p.entry}() · ${p.src_lines} lines`), " ");
      const run = el("button", { dataset: { op: "POST /api/v1/programs/{name}/run" } }, "Run");
      run.addEventListener("click", async () => {
        const res = await api("POST", `/api/v1/programs/${encodeURIComponent(p.name)}/run`, { wait: false });
        if (res.ok) {
          say(`program ${p.name}: job #${res.body.id}`);
          track(res.body.id);
        }
      });
      li.append(run);
      return li;
    }),
  );
  applyRole();
}

/** The OpenAPI document: plugin routes and their schemas, the role each operation needs. */
async function loadDoc() {
  const d = await api("GET", "/openapi.json");
  if (d.ok) state.doc = d.body;
}

async function loadPlugins() {
  const r = await api("GET", "/api/v1/plugins");
  if (!r.ok) return;
  const box = $("plugins");
  renderPlugins(box, r.body, state.doc, async (route, values) => {
    const res =
      route.method === "GET"
        ? await api("GET", `${route.url}?${new URLSearchParams(values)}`)
        : await api(route.method, route.url, values);
    await loadControl(); // re-enables what the role allows
    return res;
  });
  applyRole();
}

// ---------------------------------------------------------------- start

async function loadState() {
  const r = await fetch("/api/v1/state", { headers: headers() });
  if (r.status === 401) {
    $("auth").hidden = false;
    say(state.token ? "the token was rejected: check it or paste another" : "a token is needed");
    return false;
  }
  if (r.status === 429) {
    $("auth").hidden = false;
    say(`too many wrong tokens from this address: try again in ${r.headers.get("retry-after") || "a few"} s`);
    return false;
  }
  if (!r.ok) {
    say(`state: HTTP ${r.status}`);
    return false;
  }
  $("auth").hidden = true;
  state.authLost = false;
  const s = await r.json();
  const m = await api("GET", "/api/v1/model");
  if (m.ok) {
    state.model = m.body;
    $("model").textContent = m.body.name;
    state.view.fit(m.body);
  } else {
    $("model").textContent = "no robot model configured: the arm cannot be drawn";
  }
  // Where the path may not go (drawn in the projections).
  const ws = await api("GET", "/api/v1/workspace");
  state.zones = ws.ok ? ws.body : null;
  // The embedded simulator's trace gives every 12 ms sample; without it
  // the path comes from the positions in the state events.
  const sim = await api("GET", "/api/v1/sim");
  state.traceApi = sim.ok;
  // The last two minutes of simulated motion, then everything new.
  if (sim.ok) state.traceSince = Math.max(0, sim.body.sim_time_s - 120);
  await loadDoc();
  await Promise.all([loadPlugins(), loadControl(), loadPrograms(), loadIo()]);
  showState(s);
  return true;
}

// ---------------------------------------------------------------- digital I/O

/** The site's names and writable outputs (GET /api/v1/io; they change only with the configuration). */
async function loadIo() {
  const [r, a] = await Promise.all([api("GET", "/api/v1/io"), api("GET", "/api/v1/io/analog")]);
  state.ioNames = { input: new Map(), output: new Map(), writable: new Set() };
  state.analogNames = { input: new Map(), output: new Map(), writable: new Set() };
  if (a.ok) {
    for (const c of a.body.inputs) if (c.name) state.analogNames.input.set(c.index, c.name);
    for (const c of a.body.outputs) {
      if (c.name) state.analogNames.output.set(c.index, c.name);
      if (c.writable) state.analogNames.writable.add(c.index);
    }
  }
  if (!r.ok) return;
  for (const s of r.body.inputs) if (s.name) state.ioNames.input.set(s.index, s.name);
  for (const s of r.body.outputs) {
    if (s.name) state.ioNames.output.set(s.index, s.name);
    if (s.writable) state.ioNames.writable.add(s.index);
  }
}

/** Lamps for the 31 inputs and outputs the controller reports; allowed outputs switch on click. */
function renderIo(io) {
  $("io-note").hidden = !!io;
  if (!io) return;
  $("io-window").textContent = `$IN / $OUT ${io.base}…${io.base + io.inputs.length - 1}`;
  const names = state.ioNames || { input: new Map(), output: new Map(), writable: new Set() };
  const row = (box, kind, values) => {
    const key = JSON.stringify([io.base, values, box.childElementCount]);
    if (box.dataset.shown === key) return;
    box.dataset.shown = key;
    if (box.childElementCount !== values.length) {
      box.replaceChildren(
        ...values.map((_, k) => {
          const index = io.base + k;
          const name = names[kind].get(index);
          const writable = kind === "output" && names.writable.has(index);
          const lamp = el(writable ? "button" : "span", { class: "lamp", dataset: { index: String(index) } }, name ? `${index} ${name}` : `${index}`);
          lamp.title = `${kind === "input" ? "$IN" : "$OUT"}[${index}]${name ? ` ${name}` : ""}${writable ? " — click to switch (PUT /api/v1/io/outputs/{signal})" : ""}`;
          if (writable) {
            lamp.dataset.op = "PUT /api/v1/io/outputs/{signal}";
            lamp.addEventListener("click", async (e) => {
              e.preventDefault();
              const on = lamp.classList.contains("on");
              await api("PUT", `/api/v1/io/outputs/${index}`, { value: !on });
            });
          }
          return lamp;
        }),
      );
      applyRole();
    }
    values.forEach((v, k) => box.children[k].classList.toggle("on", v));
  };
  row($("io-outputs"), "output", io.outputs);
  row($("io-inputs"), "input", io.inputs);
}

/**
 * The analog channels the controller reports ($ANIN/$ANOUT 1..8): a cell per
 * channel with its name and value; a named output the site allows gets a
 * field and a Set button (PUT /api/v1/io/analog-outputs/{signal}).
 */
function renderAnalog(analog) {
  $("analog-box").hidden = !analog;
  if (!analog) return;
  const names = state.analogNames || { input: new Map(), output: new Map(), writable: new Set() };
  const box = $("io-analog");
  if (!box.childElementCount) {
    const cell = (kind, k) => {
      const index = k + 1;
      const name = names[kind].get(index);
      const label = `${kind === "input" ? "$ANIN" : "$ANOUT"}[${index}]${name ? ` ${name}` : ""}`;
      const value = el("b", { class: "analog-value" }, "–");
      const c = el("span", { class: "lamp analog", dataset: { kind, index: String(index) }, title: label }, `${label} `, value);
      if (kind === "output" && names.writable.has(index)) {
        const field = el("input", { type: "number", min: -1, max: 1, step: 0.001, value: "0", class: "analog-field", title: `${label}: −1…1` });
        const set = el("button", { class: "small analog-set", dataset: { op: "PUT /api/v1/io/analog-outputs/{signal}" }, title: `Set ${label} (PUT /api/v1/io/analog-outputs/${index})` }, "Set");
        set.addEventListener("click", async (e) => {
          e.preventDefault();
          const v = Number(field.value);
          if (!Number.isFinite(v) || v < -1 || v > 1) {
            field.setCustomValidity("−1…1");
            field.reportValidity();
            return;
          }
          field.setCustomValidity("");
          await api("PUT", `/api/v1/io/analog-outputs/${index}`, { value: v });
        });
        c.append(" ", field, set);
      }
      return c;
    };
    box.replaceChildren(...analog.outputs.map((_, k) => cell("output", k)), ...analog.inputs.map((_, k) => cell("input", k)));
    applyRole();
  }
  for (const [kind, values] of [["output", analog.outputs], ["input", analog.inputs]]) {
    values.forEach((v, k) => {
      const c = box.querySelector(`[data-kind='${kind}'][data-index='${k + 1}'] .analog-value`);
      if (c) c.textContent = fmt(v, 3);
    });
  }
}

/** After the stream was down (service restarted, network lost): start from the service's state again. */
async function resync() {
  state.jobs.clear();
  state.plans.clear();
  state.mine.clear();
  showPlans();
  const r = await api("GET", "/api/v1/jobs?limit=20");
  if (r.ok) r.body.reverse().forEach(showJob);
  renderJobs();
  if (state.traceApi) {
    const sim = await api("GET", "/api/v1/sim");
    // A restarted simulator starts its clock again: read from its start.
    if (sim.ok && sim.body.sim_time_s < (state.traceSince ?? 0)) {
      state.traceSince = 0;
      state.traceSeen.clear();
    }
  }
  await loadControl();
  const s = await api("GET", "/api/v1/state");
  if (s.ok) showState(s.body);
}

/** The stream was closed for good (e.g. 401): ask for a token if that is why, else try again (continuing from the last event seen). */
async function reconnect() {
  const r = await fetch("/api/v1/state", { headers: headers() }).catch(() => null);
  if (r && r.status === 401) {
    $("auth").hidden = false;
    say("the token was rejected or revoked: paste another");
    return;
  }
  if (state.stream) state.stream.close();
  listen();
}
state.reconnect = reconnect;

async function start() {
  const r = await api("GET", "/api/v1/jobs?limit=20");
  if (r.ok) r.body.reverse().forEach(showJob);
  if (state.lastEventId === null) await loadHistory();
  if (state.stream) state.stream.close();
  listen();
  // Control and role change without events (leases lapse): refresh now and then.
  state.controlTimer = state.controlTimer || setInterval(loadControl, 10000);
}

state.view = new ArmView($("arm"));
// Touch screens: the 3D view scrolls the page until asked to turn.
$("turn-view").hidden = state.view.interactive;
$("turn-view").addEventListener("click", () => {
  state.view.setInteractive(!state.view.interactive);
  $("turn-view").textContent = state.view.interactive ? "Done turning" : "Turn / zoom";
});
// Seen from above with the robot at the bottom: X up, Y to the left (a drawing reads upright).
state.top = new Projection($("top"), 1, 0, "top (X ↑, Y ←)", true);
state.side = new Projection($("side"), 0, 2, "side (X →, Z ↑)");

$("token-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  state.token = $("token").value.trim();
  $("token").value = "";
  sessionStorage.setItem("kb-token", state.token);
  if (await loadState()) {
    say("");
    await start();
  }
  state.ready = true;
});

if (await loadState()) await start();
state.ready = true;

// kuka-bridge dashboard: talks only to the public API (GET /api/v1/state,
// the event stream, POST /api/v1/stop), with the token of this tab when
// access control is on.
const $ = (id) => document.getElementById(id);
const state = { token: sessionStorage.getItem("kb-token") || "", jobs: new Map() };
window.dashboard = state; // for tests and the curious

function headers() {
  return state.token ? { Authorization: `Bearer ${state.token}` } : {};
}

function say(text) {
  $("message").textContent = text;
}

function showState(s) {
  state.robot = s;
  const c = $("connection");
  c.textContent = s.connection;
  c.className = `pill ${s.connection}`;
  const p = s.position;
  const rows = p
    ? [["X", p.x], ["Y", p.y], ["Z", p.z], ["A", p.a], ["B", p.b], ["C", p.c], ["S", p.s], ["T", p.t]]
    : [];
  $("pose").tBodies[0].replaceChildren(
    ...rows.map(([k, v]) => {
      const tr = document.createElement("tr");
      tr.innerHTML = `<td>${k}</td><td>${typeof v === "number" ? v.toFixed(k.length === 1 && "ST".includes(k) ? 0 : 3) : "–"}</td>`;
      return tr;
    }),
  );
}

function showJob(job) {
  state.jobs.set(job.id, job);
  const ids = [...state.jobs.keys()].sort((a, b) => b - a).slice(0, 20);
  $("jobs").replaceChildren(
    ...ids.map((id) => {
      const j = state.jobs.get(id);
      const li = document.createElement("li");
      li.value = id;
      li.className = j.state;
      li.textContent = `#${id} ${j.operation} ${j.state}${j.error ? ` — ${j.error.code}: ${j.error.detail}` : ""}`;
      return li;
    }),
  );
}

async function loadState() {
  const r = await fetch("/api/v1/state", { headers: headers() });
  if (r.status === 401) {
    $("auth").hidden = false;
    say("a token is needed");
    return false;
  }
  if (!r.ok) {
    say(`state: HTTP ${r.status}`);
    return false;
  }
  $("auth").hidden = true;
  showState(await r.json());
  return true;
}

function listen() {
  const q = state.token ? `?access_token=${encodeURIComponent(state.token)}` : "";
  const events = new EventSource(`/api/v1/events${q}`);
  events.addEventListener("state", (e) => showState(JSON.parse(e.data)));
  events.addEventListener("job", (e) => showJob(JSON.parse(e.data)));
  events.onerror = () => say(events.readyState === EventSource.CLOSED ? "event stream closed" : "reconnecting…");
  events.onopen = () => say("");
  state.events = events;
}

$("stop").addEventListener("click", async () => {
  const r = await fetch("/api/v1/stop", { method: "POST", headers: headers() });
  const body = await r.json().catch(() => ({}));
  say(r.ok ? "stopped" : `stop refused: ${body.code || r.status} ${body.detail || ""}`);
});

$("token-form").addEventListener("submit", async (e) => {
  e.preventDefault();
  state.token = $("token").value.trim();
  sessionStorage.setItem("kb-token", state.token);
  if (await loadState()) listen();
});

fetch("/health")
  .then((r) => r.json())
  .then((h) => ($("simulated").hidden = !h.simulated))
  .catch(() => {});
if (await loadState()) listen();
state.ready = true;

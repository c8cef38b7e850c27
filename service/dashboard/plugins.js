// The plugins panel: each installed plugin with its routes, each route a
// form generated from its JSON schema — the request body (POST) or query
// parameters (GET) as listed in /openapi.json become labelled inputs; the
// form's values become the JSON body or the query string.
import { el } from "./dom.js";

/** Resolves a local `$ref` (`#/components/schemas/...`) against the OpenAPI document. */
function deref(schema, doc) {
  let s = schema || {};
  for (let i = 0; i < 8 && s.$ref; i++) {
    s = s.$ref.replace(/^#\//, "").split("/").reduce((o, k) => (o ? o[k] : undefined), doc) || {};
  }
  return s;
}

/** The fields of an operation: [{name, schema, required, example}] from its body schema (with its first example) or query parameters. */
function fieldsOf(op, doc) {
  const body = op.requestBody?.content?.["application/json"]?.schema;
  if (body) {
    const s = deref(body, doc);
    const required = new Set(s.required || []);
    const example = (s.examples || [])[0] || {};
    // In the schema's order (as /openapi.json lists the properties; JSON.parse keeps it).
    return Object.entries(s.properties || {}).map(([name, p]) => ({ name, schema: deref(p, doc), required: required.has(name), example: example[name] }));
  }
  return (op.parameters || [])
    .filter((p) => p.in === "query")
    .map((p) => ({ name: p.name, schema: deref(p.schema, doc), required: !!p.required }));
}

function typeOf(schema) {
  const t = Array.isArray(schema.type) ? schema.type.find((x) => x !== "null") : schema.type;
  return t || "string";
}

/** Builds the inputs of `fields` into `form`. */
function buildInputs(form, fields) {
  for (const f of fields) {
    const label = document.createElement("label");
    const type = typeOf(f.schema);
    let input;
    if (Array.isArray(f.schema.enum)) {
      input = document.createElement("select");
      for (const v of f.schema.enum) input.append(new Option(String(v), JSON.stringify(v)));
      if (f.schema.default !== undefined) input.value = JSON.stringify(f.schema.default);
    } else if (type === "boolean") {
      input = document.createElement("input");
      input.type = "checkbox";
      input.checked = f.schema.default === true;
    } else {
      input = document.createElement("input");
      input.type = type === "number" || type === "integer" ? "number" : "text";
      if (input.type === "number") input.step = type === "integer" ? "1" : "any";
      if (f.schema.minimum !== undefined) input.min = f.schema.minimum;
      if (f.schema.maximum !== undefined) input.max = f.schema.maximum;
      if (f.schema.default !== undefined) input.value = typeof f.schema.default === "object" ? JSON.stringify(f.schema.default) : f.schema.default;
      if (f.example !== undefined) input.placeholder = typeof f.example === "object" ? JSON.stringify(f.example) : String(f.example);
      else if (type === "object" || type === "array") input.placeholder = "JSON";
    }
    input.name = f.name;
    input.dataset.type = type;
    input.required = f.required && type !== "boolean";
    label.title = f.schema.description || "";
    label.append(`${f.name}${f.required ? " *" : ""}`, input);
    form.append(label);
  }
}

/** The form's values as an object; empty optional fields are left out. Throws on bad JSON. */
function valuesOf(form) {
  const out = {};
  for (const input of form.querySelectorAll("input, select")) {
    if (!input.name) continue;
    const type = input.dataset.type;
    if (input.tagName === "SELECT") out[input.name] = JSON.parse(input.value);
    else if (type === "boolean") out[input.name] = input.checked;
    else if (input.value === "") continue;
    else if (type === "number" || type === "integer") out[input.name] = Number(input.value);
    else if (type === "object" || type === "array") out[input.name] = JSON.parse(input.value);
    else out[input.name] = input.value;
  }
  return out;
}

/**
 * Shows `plugins` (GET /api/v1/plugins) in `box`, one form per route;
 * `call(route, values)` performs a call and resolves to {status, body}.
 */
export function renderPlugins(box, plugins, doc, call) {
  if (!plugins.length) {
    box.replaceChildren(el("p", { class: "muted" }, "none installed"));
    return;
  }
  box.replaceChildren(
    ...plugins.map((plugin) => {
      const div = el("details", { class: "plugin" }, el("summary", {}, el("b", {}, plugin.name), ` ${plugin.version || ""} `, el("small", {}, plugin.status)));
      div.open = plugins.length <= 3; // a few: open; many: a list to expand
      for (const route of plugin.routes) div.append(routeForm(plugin, route, doc, call));
      return div;
    }),
  );
}

function routeForm(plugin, route, doc, call) {
  const op = doc?.paths?.[route.url]?.[route.method.toLowerCase()];
  const form = el("form", { class: "plugin-route", dataset: { url: route.url } }, el("h4", {}, `${route.method} ${route.url.replace(`/api/v1/plugins/${plugin.name}`, "")}`), el("p", {}, route.summary));
  buildInputs(form, op ? fieldsOf(op, doc) : []);
  const go = el("button", { dataset: { op: `${route.method} ${route.url}` } }, "Call");
  const out = el("pre");
  form.append(go, out);
  form.addEventListener("submit", async (e) => {
    e.preventDefault();
    if (go.disabled) return;
    let values;
    try {
      values = valuesOf(form);
    } catch (err) {
      out.textContent = `bad JSON in a field: ${err.message}`;
      return;
    }
    go.disabled = true;
    out.textContent = "running…";
    const res = await call(route, values);
    out.textContent = `${res.status}\n${JSON.stringify(res.body, null, 2)}`;
  });
  return form;
}

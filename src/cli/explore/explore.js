// The explorer page: sliders → the URL's query → pictures and checks from the API.
"use strict";

const state = { design: null, values: {}, ranges: {}, depth: 6, yaw: 30, pitch: 35, preview: 3, map: null, view3d: false, seq: { picture: 0, map: 0, dimension: 0 } };
// The deepest evaluation the server takes (its MAX_DEPTH); the depth slider's end.
const MAX_DEPTH = 16;
const $ = (id) => document.getElementById(id);
// This page's slots on the server: a newer picture (or map) of this page cancels its older one.
const session = Math.random().toString(36).slice(2);

function query(extra) {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(state.values)) q.set(k, v);
  for (const [k, v] of Object.entries(extra || {})) q.set(k, v);
  return q.toString();
}

function saveUrl() {
  history.replaceState(null, "", "?" + query({ depth: state.depth, view: `${state.yaw},${state.pitch}` }));
}

// The reason of a refused request (its JSON `error`, else its status).
async function reason(response) {
  try { return (await response.json()).error || `HTTP ${response.status}`; } catch (e) { return `HTTP ${response.status}`; }
}

// A refusal or a time-out shown where the picture (or map) would be, with its reason; null hides it.
function refusal(id, message) {
  const box = $(id + "-refusal");
  box.hidden = message === null;
  box.textContent = message === null ? "" : message;
  if (message !== null && !$(id).src) $(id).style.visibility = "hidden"; // no broken image behind it
}

// A request's answer, or null when it failed to reach the server at all.
async function get(url) {
  try { return await fetch(url); } catch (e) { return null; }
}

async function picture(coarse) {
  const depth = coarse ? Math.min(state.depth, state.preview) : state.depth;
  const side = Math.min(900, Math.round($("picture").clientWidth || 600));
  const seq = ++state.seq.picture;
  const url = "api/picture.png?" + query({ depth, size: `${side}x${side}`, view: `${state.yaw},${state.pitch}`, slot: `picture-${session}`, seq });
  const response = await get(url);
  if (seq !== state.seq.picture) return; // a newer picture is coming
  if (response === null) { refusal("picture", "the server does not answer (is bcifs explore still running?)"); return; }
  if (response.status === 409) return; // superseded
  if (!response.ok) {
    const error = await reason(response);
    $("status").textContent = error;
    $("picture").style.opacity = 0.25; // a divergent point is shown as such, not drawn
    refusal("picture", error);
    return;
  }
  $("status").textContent = coarse && depth < state.depth ? `preview at depth ${depth}` : "";
  $("picture").style.opacity = 1;
  $("picture").style.visibility = "visible";
  refusal("picture", null);
  $("picture").src = URL.createObjectURL(await response.blob());
}

async function check() {
  const response = await get("api/check?" + query());
  if (response === null) { $("verdict").textContent = "the server does not answer"; return; }
  const body = await response.json();
  if (!response.ok) { $("verdict").textContent = body.error; $("verdict").className = "diverges"; return; }
  const c = body.check;
  const verdict = c.converges === true ? "converges" : c.converges === false ? "diverges" : "undecided";
  $("verdict").className = verdict;
  const jsr = c.jsr ? `JSR ∈ [${c.jsr.lower.toFixed(5)}, ${c.jsr.upper === null ? "?" : c.jsr.upper.toFixed(5)}]` : "";
  const witness = c.jsr && c.jsr.witness ? ` witness ${c.jsr.witness.join(" ")}` : "";
  $("verdict").textContent = `${verdict}; ${jsr}${verdict === "diverges" ? witness : ""}`;
  const lines = [];
  if (body.curve) {
    const k = body.curve;
    if (k.directions) lines.push(`half-tangents in the model: at the start ${fmt(k.directions.start)}, at the end ${fmt(k.directions.end)}`);
    else if (k.half_tangents) lines.push(`half-tangents (barycentric): start ${fmt(k.half_tangents.start)}, end ${fmt(k.half_tangents.end)}`);
    if (k.junction_angle_deg !== null) lines.push(`junction angle between the halves ${k.junction_angle_deg.toFixed(3)}°`);
    lines.push(`region ${k.region === null ? "undecided" : k.region} (Sokolov et al. 2010 Fig. 8): ${k.region_meaning || "not decided"}`);
    lines.push(`C1 necessary condition (collinear half-tangents): ${k.c1_necessary}`);
  }
  $("check").textContent = lines.join("\n");
  // One dimension at a time for this page: a newer one cancels the older on the server.
  const seq = ++state.seq.dimension;
  const d = await get("api/dimension?" + query({ slot: `dimension-${session}`, seq }));
  if (seq !== state.seq.dimension || d === null || d.status === 409) return;
  if (d.ok) {
    const dim = await d.json();
    if (dim.box_dimension !== null) $("check").textContent += `\nbox-counting dimension ${dim.box_dimension.toFixed(4)}`;
  } else {
    $("check").textContent += `\nbox-counting dimension: ${await reason(d)}`;
  }
}

const fmt = (v) => "(" + v.map((x) => Number(x).toFixed(4)).join(", ") + ")";

function exports() {
  for (const ext of ["obj", "ply", "glb", "png", "toml"]) {
    $("export-" + ext).href = `api/export.${ext}?` + query({ depth: state.depth });
  }
}

function update(coarse) {
  saveUrl();
  exports();
  if (state.view3d) scene(coarse); else picture(coarse);
  if (!coarse) check();
  marker();
}

// A slider per parameter over its range (where the bounds prove convergence around the
// default, from the server), the range editable: two number boxes under the slider.
function slider(p) {
  const label = document.createElement("label");
  const value = document.createElement("span");
  value.className = "value";
  const input = document.createElement("input");
  input.type = "range";
  input.id = "param-" + p.name;
  const setRange = () => {
    const [lo, hi] = state.ranges[p.name];
    Object.assign(input, { min: lo, max: hi, step: (hi - lo) / 1000 });
    input.value = state.values[p.name];
  };
  setRange();
  const bounds = document.createElement("span");
  bounds.className = "range";
  const box = (i) => {
    const b = document.createElement("input");
    Object.assign(b, { type: "number", step: "any", value: state.ranges[p.name][i], title: i ? "slider's upper end" : "slider's lower end" });
    b.id = `range-${p.name}-${i}`;
    b.addEventListener("change", () => {
      const r = state.ranges[p.name].slice();
      r[i] = Number(b.value);
      if (!(Number.isFinite(r[0]) && Number.isFinite(r[1]) && r[0] < r[1])) { b.value = state.ranges[p.name][i]; return; }
      state.ranges[p.name] = r;
      setRange();
      map();
    });
    return b;
  };
  bounds.append("range ", box(0), " to ", box(1));
  label.append(p.name, value, input, bounds);
  const show = () => { value.textContent = Number(state.values[p.name]).toPrecision(5); };
  input.addEventListener("input", () => { state.values[p.name] = Number(input.value); show(); update(true); });
  input.addEventListener("change", () => update(false));
  show();
  return label;
}

// "Fit to…": the chosen file (points, a mesh, a picture) uploaded; the sliders move to the fitted member.
async function fitTo(file) {
  $("fit-status").textContent = `fitting to ${file.name}…`;
  let response = null;
  try { response = await fetch("api/fit?name=" + encodeURIComponent(file.name), { method: "POST", body: await file.arrayBuffer() }); } catch (e) { response = null; }
  if (!response || !response.ok) { $("fit-status").textContent = "not fitted: " + (response ? await reason(response) : "no answer"); return; }
  const report = await response.json();
  for (const [name, v] of Object.entries(report.parameters)) {
    if (!(name in state.values)) continue;
    state.values[name] = v;
    const [lo, hi] = state.ranges[name];
    if (v < lo || v > hi) state.ranges[name] = [Math.min(lo, v), Math.max(hi, v)];
    const input = $("param-" + name);
    Object.assign(input, { min: state.ranges[name][0], max: state.ranges[name][1] });
    input.value = v;
    // The slider snaps to its steps: the fitted value itself is the state, and shown.
    state.values[name] = v;
    input.previousElementSibling.textContent = Number(v).toPrecision(5);
  }
  const verdict = report.converges ? "proven to converge" : "not proven to converge";
  $("fit-status").textContent = `fitted to ${file.name}: residual ${report.residual.toExponential(2)}, ${verdict}` + (report.reason ? ` (${report.reason})` : "") + (report.interrupted ? " (the time budget stopped it: the best member so far)" : "");
  update(false);
  map();
}

// The map spans the slider's range and half as much again on each side (where it diverges).
function mapRange(p) {
  const [lo, hi] = state.ranges[p.name];
  const w = hi - lo;
  return [lo - w / 2, hi + w / 2];
}

async function map() {
  const params = state.design.parameters;
  if (params.length === 0) { $("mapnote").textContent = "This design has no free parameter."; $("mapbox").hidden = true; return; }
  // One free parameter (the ternary scheme's ω): a strip over it.
  const line = params.length === 1;
  $("mapy").hidden = line;
  const [x, y] = [$("mapx").value, line ? null : $("mapy").value];
  if (x === y) { $("mapnote").textContent = "Choose two different parameters."; return; }
  const px = params.find((p) => p.name === x), py = params.find((p) => p.name === y);
  state.map = { x, y, xr: mapRange(px), yr: line ? null : mapRange(py) };
  $("xname").textContent = x;
  $("xlo").textContent = state.map.xr[0].toPrecision(3); $("xhi").textContent = state.map.xr[1].toPrecision(3);
  $("yname").textContent = line ? "" : y;
  $("ylo").textContent = line ? "" : `${y} from ${state.map.yr[0].toPrecision(3)} (bottom)`;
  $("yhi").textContent = line ? "" : `to ${state.map.yr[1].toPrecision(3)} (top)`;
  $("mapnote").textContent = "Click to set the parameters.";
  const kind = $("mapkind").value;
  $("threshold-box").hidden = kind !== "smooth";
  const seq = ++state.seq.map;
  const q = new URLSearchParams({ x, xr: state.map.xr.join(":"), kind, size: line ? 384 : 192, slot: `map-${session}`, seq });
  if (!line) { q.set("y", y); q.set("yr", state.map.yr.join(":")); }
  if (kind === "smooth") q.set("threshold", $("threshold").value);
  const response = await get("api/map.png?" + q.toString());
  if (seq !== state.seq.map) return;
  if (response === null) { refusal("map", "the server does not answer (is bcifs explore still running?)"); return; }
  if (response.status === 409) return; // superseded
  if (!response.ok) {
    const error = await reason(response);
    $("mapnote").textContent = error;
    refusal("map", error);
    return;
  }
  refusal("map", null);
  $("map").style.visibility = "visible";
  $("map").src = URL.createObjectURL(await response.blob());
  marker();
}

function marker() {
  if (!state.map) return;
  const { x, y, xr, yr } = state.map;
  const u = (state.values[x] - xr[0]) / (xr[1] - xr[0]), v = y === null ? 0.5 : (yr[1] - state.values[y]) / (yr[1] - yr[0]);
  Object.assign($("marker").style, { left: `${100 * u}%`, top: `${100 * v}%` });
}

$("map").addEventListener("click", (event) => {
  const box = $("map").getBoundingClientRect();
  const { x, y, xr, yr } = state.map;
  state.values[x] = xr[0] + (event.clientX - box.left) / box.width * (xr[1] - xr[0]);
  if (y !== null) state.values[y] = yr[1] - (event.clientY - box.top) / box.height * (yr[1] - yr[0]);
  for (const n of y === null ? [x] : [x, y]) {
    const input = $("param-" + n);
    input.value = state.values[n];
    input.previousSibling.textContent = Number(state.values[n]).toPrecision(5);
  }
  update(false);
});

// Drag on the picture to turn a surface (yaw with x, pitch with y): coarse while dragging.
function dragToTurn() {
  let from = null;
  $("picture").addEventListener("mousedown", (e) => { from = { x: e.clientX, y: e.clientY, yaw: state.yaw, pitch: state.pitch }; e.preventDefault(); });
  window.addEventListener("mousemove", (e) => {
    if (!from) return;
    state.yaw = Math.round(((from.yaw + (e.clientX - from.x) / 2 + 540) % 360) - 180);
    state.pitch = Math.round(Math.max(-89, Math.min(89, from.pitch + (e.clientY - from.y) / 2)));
    $("yaw").value = state.yaw; $("pitch").value = state.pitch;
    $("view-value").textContent = `${state.yaw}°, ${state.pitch}°`;
    update(true);
  });
  window.addEventListener("mouseup", () => { if (from) { from = null; update(false); } });
}

async function start() {
  state.design = await (await fetch("api/design")).json();
  $("name").textContent = state.design.name;
  $("description").textContent = state.design.description;
  document.title = `bcifs explore: ${state.design.name}`;
  const given = new URLSearchParams(location.search);
  // A value of the URL that is not a finite number is left for the default.
  const number = (key) => (given.has(key) && given.get(key).trim() !== "" && Number.isFinite(Number(given.get(key))) ? Number(given.get(key)) : null);
  for (const p of state.design.parameters) {
    state.values[p.name] = number(p.name) ?? p.default;
    // A value given outside the convergence range widens the slider to it.
    state.ranges[p.name] = [Math.min(p.range[0], state.values[p.name]), Math.max(p.range[1], state.values[p.name])];
  }
  const depth = number("depth");
  if (Number.isInteger(depth) && depth >= 0 && depth <= MAX_DEPTH) state.depth = depth;
  const view = (given.get("view") || "").split(",").map((t) => (t.trim() === "" ? NaN : Number(t)));
  if (view.length === 2 && view.every(Number.isFinite)) [state.yaw, state.pitch] = [view[0], Math.max(-89, Math.min(89, view[1]))];
  $("depth").max = MAX_DEPTH;
  for (const p of state.design.parameters) $("sliders").append(slider(p));
  $("depth").value = state.depth; $("yaw").value = state.yaw; $("pitch").value = state.pitch;
  const showDepth = () => { $("depth-value").textContent = state.depth; $("view-value").textContent = `${state.yaw}°, ${state.pitch}°`; };
  $("depth").addEventListener("input", () => { state.depth = Number($("depth").value); showDepth(); });
  $("depth").addEventListener("change", () => update(false));
  // The 3D view turns in the browser: no new scene for a new view.
  for (const id of ["yaw", "pitch"]) {
    $(id).addEventListener("input", () => { state[id] = Number($(id).value); showDepth(); if (state.view3d) { draw3d(); saveUrl(); } else update(true); });
    $(id).addEventListener("change", () => { if (!state.view3d) update(false); });
  }
  showDepth();
  for (const [i, p] of state.design.parameters.entries()) {
    for (const [select, at] of [["mapx", 0], ["mapy", 1]]) {
      const option = new Option(p.name, p.name, false, i === at);
      $(select).append(option);
    }
  }
  // Regions, angles and their smoothness are of curve families: not offered for a surface.
  if (!state.design.curve_maps) for (const kind of ["region", "angle", "smooth"]) $("mapkind").querySelector(`option[value="${kind}"]`).remove();
  for (const id of ["mapx", "mapy", "mapkind", "threshold"]) $(id).addEventListener("change", map);
  $("fit-file").addEventListener("change", () => { const f = $("fit-file").files[0]; if (f) fitTo(f); });
  // The page going away stops its pictures and maps on the server.
  window.addEventListener("pagehide", () => navigator.sendBeacon("api/bye?session=" + session));
  dragToTurn();
  // Surfaces and solids have a 3D view.
  if (state.design.mesh) {
    $("toggle3d-box").hidden = false;
    $("toggle3d").addEventListener("change", () => show3d($("toggle3d").checked));
    controls3d();
  }
  update(false);
  map();
  document.body.dataset.ready = "yes";
}

start();

// The explorer page: controls -> query string -> /api/view -> drawing. No framework, nothing
// loaded from elsewhere. Every number is the server's (the library's); the page only draws.
"use strict";

// the device and the wall: key, label, unit, factor (shown = SI * factor), slider min, max
// (shown units), log scale, default (SI), group. The elements' controls are built from the
// element list the server describes (/api/params), so a new element appears by itself.
const CONTROLS = [
  ["mass", "mass m", "kg", 1, 0.01, 2, true, 0.1, "device"],
  ["period", "period T", "ms", 1000, 0.1, 10, true, 0.001, "device"],
  ["damping", "damping b", "N s/m", 1, 0, 50, false, 0, "device"],
  ["delay", "delay", "samples", 1, 0, 10, false, 1, "device"],
  ["stiffness", "stiffness K", "N/m", 1, 0, 30000, false, 10800, "wall"],
  ["wall_damping", "damping B", "N s/m", 1, -50, 150, false, 42.5, "wall"],
];
const DEVICE_KEYS = CONTROLS.map((c) => c[0]);
const STEPS = 1000; // slider resolution

const state = {}; // every value, in SI units
const named = {}; // element parameter keyword -> whether it is part of the loop
const enabled = {}; // element -> whether it is switched on
const params = {}; // keyword -> its description from the element list
const ELEMENTS = {}; // element -> its parameters' keywords, in the list's order
const spec = {}; // the numeric controls, by key
let view = null; // the last view drawn
let frame = null; // the plane's scales, kept while the wall is dragged
let dragging = false;
let seq = 0, drawnSeq = 0, inFlight = false, pending = false, timer = null;
let inputTime = null;
const latencies = [], fetches = [];
// for tests and the curious: the state, the last view, the update times, whether idle
window.explorer = {
  latencies, fetches, state, named, enabled,
  get view() { return view; },
  get seq() { return drawnSeq; },
  get idle() { return !inFlight && !pending && timer === null; },
};

function fmt(x, digits = 6) {
  if (x === null || x === undefined || !isFinite(x)) return String(x);
  return Number(x.toPrecision(digits)).toString();
}

function grouped(x) {
  return Math.round(x).toLocaleString("en-US");
}

function sliderOf(c, si) {
  const v = si * c.factor;
  if (c.log) {
    const t = (Math.log(Math.max(v, c.min)) - Math.log(c.min)) / (Math.log(c.max) - Math.log(c.min));
    return Math.round(Math.min(Math.max(t, 0), 1) * STEPS);
  }
  return Math.round(Math.min(Math.max((v - c.min) / (c.max - c.min), 0), 1) * STEPS);
}

function valueOf(c, pos) {
  const t = pos / STEPS;
  let v = c.log ? Math.exp(Math.log(c.min) + t * (Math.log(c.max) - Math.log(c.min)))
    : c.min + t * (c.max - c.min);
  if (c.count) return Math.round(v);
  if (c.key === "delay") return Math.round(v * 20) / 20; // 1/20 of a sample
  v = Number(v.toPrecision(3));
  return v / c.factor;
}

// one row: label, slider and typed field of a numeric control, or a choice
function row(c, parent, label) {
  const row = document.createElement("div");
  row.className = "row";
  row.dataset.key = c.key;
  if (c.choices) {
    row.innerHTML = `<label for="${c.key}"></label><select id="${c.key}" data-key="${c.key}"></select>`;
    for (const n of c.choices) {
      const o = document.createElement("option");
      o.value = o.textContent = n;
      row.querySelector("select").appendChild(o);
    }
  } else {
    row.innerHTML = `<label for="${c.key}"></label>` +
      `<input type="range" id="${c.key}-slider" min="0" max="${STEPS}" step="1">` +
      `<input type="number" id="${c.key}" data-key="${c.key}" step="any">`;
  }
  row.querySelector("label").append(label);
  parent.appendChild(row);
  if (c.choices) {
    row.querySelector("select").addEventListener("change", (e) => {
      inputTime = performance.now();
      state[c.key] = e.target.value;
      changed(c.key);
    });
    return row;
  }
  row.querySelector("input[type=range]").setAttribute("aria-label", c.label);
  const slider = row.querySelector("input[type=range]");
  const field = row.querySelector("input[type=number]");
  slider.addEventListener("input", () => {
    inputTime = performance.now();
    state[c.key] = valueOf(c, Number(slider.value));
    field.value = shown(c, state[c.key]);
    changed(c.key);
  });
  field.addEventListener("change", () => {
    inputTime = performance.now();
    const v = Number(field.value) / c.factor;
    state[c.key] = field.value.trim() === "" || !isFinite(v) ? field.value : v;
    slider.value = sliderOf(c, Number(field.value) / c.factor);
    changed(c.key);
  });
  return row;
}

function build() {
  for (const [key, label, unit, factor, min, max, log, def, group] of CONTROLS) {
    const c = { key, label, unit, factor, min, max, log, def, group };
    spec[key] = c;
    state[key] = def;
    row(c, document.getElementById(group), label + (unit ? " (" + unit + ")" : ""));
  }
  const box = document.getElementById("elements");
  for (const p of Object.values(params)) {
    let fs = document.getElementById(p.element);
    if (!fs) {
      fs = document.createElement("fieldset");
      fs.id = p.element;
      fs.className = "element";
      fs.innerHTML = `<legend><label><input type="checkbox" data-element="${p.element}"> </label></legend>`;
      fs.querySelector("label").append(p.element_title);
      box.appendChild(fs);
      ELEMENTS[p.element] = [];
      enabled[p.element] = false;
      fs.querySelector("input").addEventListener("change", (e) => {
        inputTime = performance.now();
        enabled[p.element] = e.target.checked;
        changed(p.element);
      });
    }
    ELEMENTS[p.element].push(p.keyword);
    const a = p.accepts;
    const c = {
      key: p.keyword, label: p.name, unit: p.unit, factor: p.factor, min: p.min, max: p.max,
      log: p.log, def: p.start, group: p.element, count: a.kind === "count",
      choices: a.kind === "choice" ? a.choices : null,
    };
    if (!c.choices) spec[p.keyword] = c;
    state[p.keyword] = c.choices ? a.choices[0] : p.start;
    named[p.keyword] = p.on;
    const use = document.createElement("input");
    use.type = "checkbox";
    use.id = "use-" + p.keyword;
    use.title = "part of the loop";
    use.addEventListener("change", () => {
      inputTime = performance.now();
      name(p.keyword, use.checked);
      changed(p.keyword);
    });
    const r = row(c, fs, shortName(p) + (p.unit ? " (" + p.unit + ")" : ""));
    r.title = p.help;
    r.querySelector("label").prepend(use);
  }
  document.getElementById("share").addEventListener("click", (e) => {
    e.preventDefault();
    navigator.clipboard?.writeText(location.href);
  });
}

// a parameter's name without its element's ("cutoff" in the velocity filter's box)
function shortName(p) {
  const el = p.element.replace(/([a-z])([A-Z])/g, "$1 $2").toLowerCase() + " ";
  return p.name.startsWith(el) ? p.name.slice(el.length) : p.name;
}

// names (or un-names) a parameter, with the ones it needs and without the ones it excludes
function name(keyword, on) {
  named[keyword] = on;
  if (!on) return;
  const p = params[keyword];
  for (const k of p.requires) named[k] = true;
  for (const k of p.conflicts) named[k] = false;
  for (const q of Object.values(params)) if (q.conflicts.includes(keyword)) named[q.keyword] = false;
}

function shown(c, si) {
  return typeof si === "number" ? Number((si * c.factor).toPrecision(12)) : si;
}

function refreshControls() {
  for (const key in spec) {
    const c = spec[key];
    document.getElementById(key).value = shown(c, state[key]);
    document.getElementById(key + "-slider").value = sliderOf(c, Number(state[key]));
  }
  for (const el in ELEMENTS) {
    document.querySelector(`input[data-element=${el}]`).checked = enabled[el];
    document.getElementById(el).classList.toggle("off", !enabled[el]);
    for (const k of ELEMENTS[el]) {
      document.getElementById("use-" + k).checked = named[k];
      document.getElementById(k).closest(".row").classList.toggle("unnamed", !named[k]);
      if (params[k].accepts.kind === "choice") document.getElementById(k).value = state[k];
    }
  }
}

// the query string of the state: the device, the wall, the parameters named of the elements
// switched on
function query() {
  const p = new URLSearchParams();
  for (const k of DEVICE_KEYS) p.set(k, state[k]);
  for (const el in ELEMENTS) {
    if (!enabled[el]) continue;
    for (const k of ELEMENTS[el]) if (named[k]) p.set(k, state[k]);
  }
  return p.toString();
}

function load(q) {
  const p = new URLSearchParams(q);
  for (const [k] of p) {
    // an element in the link: its parameters are those the link names
    if (k in params && !enabled[params[k].element]) {
      const el = params[k].element;
      enabled[el] = true;
      for (const j of ELEMENTS[el]) named[j] = false;
    }
  }
  for (const [k, v] of p) {
    if (k in params) {
      named[k] = true;
      state[k] = params[k].accepts.kind === "choice" ? v : Number(v);
    } else if (k in spec) {
      state[k] = Number(v);
    }
  }
}

function changed(what) {
  if (what !== "stiffness" && what !== "wall_damping" && !dragging) frame = null;
  refreshControls();
  schedule();
}

// the debounce: one request at a time; the changes made while it runs are sent, the latest
// state only, when it returns
function schedule() {
  clearTimeout(timer);
  timer = setTimeout(send, 0);
}

async function send() {
  timer = null;
  if (inFlight) { pending = true; return; }
  inFlight = true;
  const q = query();
  const my = ++seq;
  const t0 = inputTime;
  document.body.dataset.status = "busy";
  history.replaceState(null, "", "?" + q);
  updateLinks(q);
  try {
    const f0 = performance.now();
    const r = await fetch("/api/view?" + q);
    const body = await r.json();
    fetches.push(performance.now() - f0);
    if (!r.ok) throw new Error(body.error || r.statusText);
    view = body;
    draw();
    showError(null);
    await new Promise((res) => requestAnimationFrame(() => res()));
    if (t0 !== null) {
      const ms = performance.now() - t0;
      latencies.push(ms);
      document.getElementById("latency").textContent = ms.toFixed(0);
    }
    document.body.dataset.status = "ready";
  } catch (e) {
    showError(String(e.message || e));
    document.body.dataset.status = "error";
  }
  drawnSeq = my;
  document.body.dataset.seq = my;
  inFlight = false;
  if (pending) { pending = false; send(); }
}

function showError(msg) {
  const e = document.getElementById("error");
  e.hidden = !msg;
  e.textContent = msg || "";
}

function updateLinks(q) {
  document.querySelectorAll("a[data-export]").forEach((a) => {
    a.href = `/api/export/${a.dataset.export}?${q}`;
  });
  document.getElementById("share").href = "?" + q;
  const flags = [`--mass ${state.mass}`, `--period ${state.period}`, `--damping ${state.damping}`,
    `--delay-samples ${state.delay}`];
  const p = new URLSearchParams(q);
  for (const [k, v] of p) if (k in params) flags.push(`--${params[k].flag} ${v}`);
  document.getElementById("commands").textContent =
    "Same on the command line: stabound amax " + flags.join(" ");
}

function setNum(id, value, text) {
  const e = document.getElementById(id);
  e.dataset.value = value;
  e.textContent = text;
}

const NS = "http://www.w3.org/2000/svg";
function el(name, attrs, parent, text) {
  const e = document.createElementNS(NS, name);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

function ticks(lo, hi, n) {
  const span = hi - lo;
  if (!(span > 0)) return [lo];
  const raw = span / n, mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) out.push(Number(v.toPrecision(12)));
  return out;
}

function axes(svg, fx, fy, xr, yr, box, xlabel, ylabel) {
  for (const t of ticks(xr[0], xr[1], 8)) {
    el("line", { x1: fx(t), x2: fx(t), y1: box.top, y2: box.bottom, class: "grid" }, svg);
    el("text", { x: fx(t), y: box.bottom + 16, "text-anchor": "middle" }, svg, fmt(t, 4));
  }
  for (const t of ticks(yr[0], yr[1], 8)) {
    el("line", { x1: box.left, x2: box.right, y1: fy(t), y2: fy(t), class: "grid" }, svg);
    el("text", { x: box.left - 6, y: fy(t) + 4, "text-anchor": "end" }, svg, fmt(t, 4));
  }
  el("rect", { x: box.left, y: box.top, width: box.right - box.left, height: box.bottom - box.top, fill: "none", class: "axis" }, svg);
  el("text", { x: (box.left + box.right) / 2, y: box.bottom + 34, "text-anchor": "middle" }, svg, xlabel);
  el("text", { x: 14, y: (box.top + box.bottom) / 2, transform: `rotate(-90 14 ${(box.top + box.bottom) / 2})`, "text-anchor": "middle" }, svg, ylabel);
}

function path(pts, fx, fy) {
  return pts.map((p, i) => (i ? "L" : "M") + fx(p[0]).toFixed(2) + " " + fy(p[1]).toFixed(2)).join("") + "Z";
}

function draw() {
  const v = view;
  setNum("kmax", v.kmax.K_max, grouped(v.kmax.K_max) + " N/m");
  setNum("kmax-b", v.kmax.B, fmt(v.kmax.B, 4) + " N s/m");
  const p = v.kmax_positive_damping;
  setNum("kmax-pos", p.K_max, grouped(p.K_max) + " N/m");
  setNum("kmax-pos-b", p.B, fmt(p.B, 4) + " N s/m");
  const w = v.wall;
  const verdict = document.getElementById("verdict");
  verdict.textContent = w.verdict;
  verdict.className = w.verdict;
  setNum("radius", w.spectral_radius, fmt(w.spectral_radius, 6));
  // no stable stiffness at this damping: the margin is undefined (null)
  setNum("margin", w.stiffness_margin, w.stiffness_margin === null ? "none: no K is stable at this B"
    : fmt(w.stiffness_margin, 4));
  setNum("klim", w.stiffness_limit, grouped(w.stiffness_limit) + " N/m");
  setNum("suggested", w.suggested.damping, fmt(w.suggested.damping, 4) + " N s/m");
  document.getElementById("suggested-margin").textContent = fmt(w.suggested.stiffness_margin, 4);
  document.getElementById("margin-wall").textContent =
    `K = ${grouped(v.margin_wall.stiffness)} N/m, B = ${fmt(v.margin_wall.wall_damping, 4)} N s/m`;
  document.getElementById("passive-note").textContent = v.passive.note ? "passive region: " + v.passive.note
    : v.passive.region.length ? "passive region: dash-dotted" : "passive region: empty (no physical damping)";
  document.getElementById("vertices").textContent = v.region_vertices;
  drawPlane();
  drawStep();
}

function planeFrame() {
  const v = view;
  let kx = 0, blo = Infinity, bhi = -Infinity;
  for (const [k, b] of v.region) { kx = Math.max(kx, k); blo = Math.min(blo, b); bhi = Math.max(bhi, b); }
  kx = Math.max(kx, state.stiffness);
  blo = Math.min(blo, state.wall_damping, 0);
  bhi = Math.max(bhi, state.wall_damping);
  const pad = (bhi - blo) * 0.08 || 1;
  return { xr: [0, kx * 1.1 || 1], yr: [blo - pad, bhi + pad] };
}

const PLANE = { left: 70, right: 625, top: 12, bottom: 390 };
function drawPlane() {
  const svg = document.getElementById("plane");
  svg.replaceChildren();
  if (!frame) frame = planeFrame();
  const { xr, yr } = frame, b = PLANE;
  const fx = (x) => b.left + (x - xr[0]) / (xr[1] - xr[0]) * (b.right - b.left);
  const fy = (y) => b.bottom - (y - yr[0]) / (yr[1] - yr[0]) * (b.bottom - b.top);
  frame.inverse = (px, py) => [xr[0] + (px - b.left) / (b.right - b.left) * (xr[1] - xr[0]),
    yr[0] + (b.bottom - py) / (b.bottom - b.top) * (yr[1] - yr[0])];
  axes(svg, fx, fy, xr, yr, b, "stiffness K (N/m)", "damping B (N s/m)");
  const clip = el("clipPath", { id: "clip" }, el("defs", {}, svg));
  el("rect", { x: b.left, y: b.top, width: b.right - b.left, height: b.bottom - b.top }, clip);
  const g = el("g", { "clip-path": "url(#clip)" }, svg);
  el("path", { d: path(view.region, fx, fy), class: "region", id: "region" }, g);
  if (view.passive.region && view.passive.region.length)
    el("path", { d: path(view.passive.region, fx, fy), class: "passive", id: "passive" }, g);
  const k = view.kmax, kp = view.kmax_positive_damping;
  el("circle", { cx: fx(k.K_max), cy: fy(k.B), r: 4, class: "kmax" }, g);
  el("circle", { cx: fx(kp.K_max), cy: fy(kp.B), r: 7, class: "kmaxpos" }, g);
  const label = el("text", { x: fx(k.K_max) - 8, y: fy(k.B) - 10, "text-anchor": "end" }, g, "K");
  el("tspan", { "baseline-shift": "sub", "font-size": "70%" }, label, "max");
  const wall = el("circle", { cx: fx(state.stiffness), cy: fy(state.wall_damping), r: 8, id: "wall-marker",
    class: "wall " + view.wall.verdict }, g);
  el("title", {}, wall, "the wall: drag it");
}

function drawStep() {
  const svg = document.getElementById("step");
  svg.replaceChildren();
  const s = view.step, b = { left: 70, right: 625, top: 10, bottom: 175 };
  const t = s.time.map((x) => x * 1000), y = s.position.map((x) => x * 1000);
  let lo = Math.min(0, ...y), hi = Math.max(...y, 0);
  if (s.final_value !== null) hi = Math.max(hi, s.final_value * 1000);
  if (!(hi > lo)) hi = lo + 1;
  const xr = [0, t[t.length - 1]], yr = [lo, hi + (hi - lo) * 0.05];
  const fx = (x) => b.left + (x - xr[0]) / (xr[1] - xr[0]) * (b.right - b.left);
  const fy = (v) => b.bottom - (v - yr[0]) / (yr[1] - yr[0]) * (b.bottom - b.top);
  axes(svg, fx, fy, xr, yr, b, "time (ms)", "x (mm)");
  if (s.final_value !== null) {
    const f = fy(s.final_value * 1000);
    el("line", { x1: b.left, x2: b.right, y1: f, y2: f, class: "reference" }, svg);
  }
  const d = t.map((x, i) => (i ? "L" : "M") + fx(x).toFixed(2) + " " + fy(Math.min(Math.max(y[i], yr[0]), yr[1])).toFixed(2)).join("");
  el("path", { d, class: "response", id: "response" }, svg);
  el("text", { x: b.right - 4, y: b.top + 14, "text-anchor": "end" }, svg, "step response to a 1 N force");
}

function setupDrag() {
  const svg = document.getElementById("plane");
  const move = (e) => {
    if (!frame || !frame.inverse) return;
    const pt = svg.createSVGPoint();
    pt.x = e.clientX; pt.y = e.clientY;
    const p = pt.matrixTransform(svg.getScreenCTM().inverse());
    const [k, bb] = frame.inverse(p.x, p.y);
    inputTime = performance.now();
    state.stiffness = Math.max(0, Number(k.toPrecision(4)));
    state.wall_damping = Number(bb.toPrecision(4));
    changed("stiffness");
  };
  svg.addEventListener("pointerdown", (e) => {
    e.preventDefault();
    dragging = true;
    svg.setPointerCapture(e.pointerId);
    move(e);
  });
  svg.addEventListener("pointermove", (e) => { if (dragging) move(e); });
  const up = () => { dragging = false; };
  svg.addEventListener("pointerup", up);
  svg.addEventListener("pointercancel", up);
}

async function start() {
  try {
    const r = await fetch("/api/params");
    for (const p of (await r.json()).params) params[p.keyword] = p;
  } catch (e) {
    showError("cannot read the element list: " + String(e.message || e));
  }
  build();
  load(location.search);
  refreshControls();
  setupDrag();
  send();
}

start();

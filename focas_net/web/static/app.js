// focas-net dashboard: one WebSocket of live frames, REST calls for the actions.
"use strict";

const $ = (id) => document.getElementById(id);
const state = { readOnly: false, machines: 0, ws: null, topic: null, machine: null, view: null,
  pmcArea: "X", pmcStart: 0, pmcError: "", versions: null, paramKey: null, macroKey: null,
  path: 1, pathsKey: null };

// Searches answer out of order when typed fast: each kind of list draws only the answer to the
// last search it sent.
const latest = { params: 0, macros: 0, fleet: 0 };
async function newest(kind, url) {
  const ticket = ++latest[kind];
  const res = await fetch(url);
  const body = await res.json();
  return ticket === latest[kind] ? { res, body } : null;
}

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "class") node.className = v;
    else if (k.startsWith("data-")) node.setAttribute(k, v);
    else node[k] = v;
  }
  for (const c of children) node.append(c);
  return node;
}

// "1 part", "2 parts": a count and its noun, as the command line writes them.
function count(n, noun) { return `${n} ${noun}${n === 1 ? "" : "s"}`; }

// What follows "#/machine/" as the user typed it ("%D9%A1" is the digit they typed).
function typedAddress(text) {
  try { return decodeURIComponent(text); } catch (e) { return text; }
}

function show(text, ok) {
  const m = $("message");
  m.textContent = text;
  m.className = ok ? "ok" : "error";
}

async function act(action, args) {
  const res = await fetch(`/api/machines/${state.machine}/actions/${action}`, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ path: state.path, ...(args || {}) }),
  });
  const body = await res.json();
  // an action that changed nothing (an alarm active already, nothing to clear) says only why
  const none = body.raised === false || body.cleared === 0;
  const said = none ? body.note : `done${body.note ? `; ${body.note}` : ""}`;
  if (body.ok) show(`${action}: ${said}`, true);
  else show(`${action} refused: ${body.ew_name ? body.ew_name + " " : ""}${body.error || ""}`, false);
  return body;
}

// -- routing and the live link -------------------------------------------------------------
function notice(text) {
  $("notice").textContent = text;
  $("notice").hidden = !text;
}

function route() {
  let m = location.hash.match(/^#\/machine\/(\d+)$/);
  notice("");
  if (!m && location.hash.startsWith("#/machine/") || m && Number(m[1]) >= state.machines) {
    // an address of no machine: say so over the fleet, never over another machine's view
    const what = typedAddress(location.hash.slice("#/machine/".length));
    const shows = state.machines === 1 ? "machine 0" : `machines 0..${state.machines - 1}`;
    notice(`${what ? `no machine '${what}'` : "no machine given"} (this dashboard shows ${shows})`);
    m = null;
  }
  $("fleet-view").hidden = !!m;
  $("machine-view").hidden = !m;
  if (m) {
    state.machine = Number(m[1]);
    state.view = null;
    state.dirKey = state.progKey = state.pmcKey = state.versions = null;
    state.paramKey = state.macroKey = state.pathsKey = null;
    state.path = 1;
    state.pmcArea = null;  // the machine's first area, until one is chosen
    state.pmcStart = 0;
    state.pmcError = "";
    $("pmc-start").value = "0";
    $("message").textContent = "";
    loadParams();
    loadMacros();
  } else {
    state.machine = null;
    $("crumb").textContent = "fleet";
  }
  subscribe();
}

function subscribe() {
  if (!state.ws || state.ws.readyState !== WebSocket.OPEN) return;
  const msg = state.machine === null
    ? { subscribe: "fleet" }
    : state.pmcArea === null
      ? { subscribe: "machine", index: state.machine, path: state.path }
      : { subscribe: "machine", index: state.machine, pmc_area: state.pmcArea,
          pmc_start: state.pmcStart, path: state.path };
  state.ws.send(JSON.stringify(msg));
}

function connect() {
  const ws = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
  state.ws = ws;
  ws.onopen = () => {
    $("link-state").textContent = "live";
    $("link-state").className = "link up";
    subscribe();
  };
  ws.onclose = () => {
    $("link-state").textContent = "disconnected";
    $("link-state").className = "link down";
    setTimeout(connect, 1000);
  };
  ws.onmessage = (ev) => {
    const msg = JSON.parse(ev.data);
    if (msg.type === "error") show(msg.error, false);
    else if (msg.type === "fleet" && state.machine === null) renderFleet(msg.data);
    else if (msg.type === "machine" && msg.data.index === state.machine) {
      renderMachine(msg.data);
      renderPmc(msg.pmc);
    }
  };
}

// -- fleet view ----------------------------------------------------------------------------
// Tiles are made once per machine and updated in place, so a click is never lost to a redraw.
const tiles = new Map();

function tileOf(t) {
  let tile = tiles.get(t.index);
  if (!tile) {
    const parts = { name: el("div", { class: "name" }), port: el("span"), mode: el("span"),
      run: el("span", { class: "run" }), program: el("span"), sequence: el("span"),
      parts: el("span", { class: "parts" }), alarm: el("div", { class: "alm" }) };
    const node = el("a", { href: `#/machine/${t.index}`, "data-index": String(t.index) },
      parts.name, el("div", { class: "row" }, parts.port, parts.mode, parts.run),
      el("div", { class: "row" }, parts.program, parts.sequence, parts.parts), parts.alarm);
    tile = { node, parts, paths: null };
    tiles.set(t.index, tile);
  }
  if (t.paths.length > 1 && (!tile.paths || tile.paths.length !== t.paths.length)) {
    // a machine of several paths: a line per path under the machine's name
    tile.paths = t.paths.map((p) => el("div", { class: "row path", "data-path": String(p.path_no) }));
    const box = el("div", { class: "paths" }, ...tile.paths);
    tile.node.replaceChildren(tile.parts.name, el("div", { class: "row" }, tile.parts.port), box,
      tile.parts.alarm);
  }
  return tile;
}

// A program number as the command line writes it: O and four digits, "none" for 0 (none).
function oNumber(n) { return n ? `O${String(n).padStart(4, "0")}` : "none"; }

function pathLine(p) {
  return `${p.path_name} ${p.mode} ${p.run} ${oNumber(p.program)} ` +
    `N${p.sequence} ${count(p.parts, "part")}` +
    (p.alarm ? ` ALM ${p.alarm}` : (p.emergency ? " EMG" : ""));
}

function setText(node, text) { if (node.textContent !== text) node.textContent = text; }

function renderFleet(data) {
  setText($("fleet-summary"),
    `${count(data.count, "machine")}, ${data.running} running, ${data.alarmed} in alarm`);
  const filter = $("fleet-filter").value.trim().toLowerCase();
  const shown = [];
  for (const t of data.machines) {
    if (filter && !t.name.toLowerCase().includes(filter)) continue;
    const tile = tileOf(t);
    const { node, parts } = tile;
    const cls = `tile ${t.run_state}${t.alarms ? " alarm" : ""}`;
    if (node.className !== cls) node.className = cls;
    setText(parts.name, t.name);
    setText(parts.port, `:${t.port}`);
    setText(parts.mode, t.mode);
    setText(parts.run, t.run);
    setText(parts.program, oNumber(t.program));
    setText(parts.sequence, `N${t.sequence}`);
    setText(parts.parts, count(t.parts, "part"));
    setText(parts.alarm, t.alarm ? `ALM ${t.alarm}` : (t.emergency ? "EMG" : "\u00a0"));
    if (tile.paths) {
      t.paths.forEach((p, i) => {
        setText(tile.paths[i], pathLine(p));
        const cls = `row path ${p.run_state}${p.alarms ? " alarm" : ""}`;
        if (tile.paths[i].className !== cls) tile.paths[i].className = cls;
      });
    }
    shown.push(node);
  }
  const box = $("fleet");
  if (box.children.length !== shown.length || shown.some((n, i) => box.children[i] !== n)) {
    box.replaceChildren(...shown);
  }
}

// -- machine view --------------------------------------------------------------------------
function setIfIdle(input, value) {
  if (document.activeElement !== input) {
    if (input.type === "checkbox") input.checked = !!value;
    else input.value = value;
  }
}

function fmt(v, d = 3) { return Number(v).toFixed(d); }

// A time as focas-net watch writes it: 1:02:03.4 (to a tenth of a second, cut, not rounded,
// from the milliseconds the wire carries)
function clock(seconds) {
  const tenths = Math.floor(Math.floor(Math.max(seconds, 0) * 1000 + 1e-6) / 100);
  const s = Math.floor(tenths / 10);
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60);
  return `${h}:${String(m).padStart(2, "0")}:${String(s % 60).padStart(2, "0")}.${tenths % 10}`;
}

// A machine of several paths: a section per path (its state and its cycle buttons), and the
// path whose details the other sections show.
function renderPaths(v) {
  const box = $("paths-box");
  box.hidden = v.path_count < 2;
  if (box.hidden) return;
  const key = `${state.machine}:${v.path_count}`;
  if (state.pathsKey !== key) {
    state.pathsKey = key;
    $("paths").replaceChildren(...v.paths.map((p) => {
      const n = p.path_no;
      const button = (what, label, cls) => el("button", { class: `small ${cls}`,
        id: `path-${n}-${what}`, "data-write": "", disabled: state.readOnly,
        onclick: () => act("cycle", { action: what, path: n }) }, label);
      return el("div", { class: "path-card", id: `path-${n}` },
        el("h3", {}, el("a", { href: "#", id: `path-${n}-show`,
          onclick: (ev) => { ev.preventDefault(); choosePath(n); } }, p.path_name)),
        el("div", { class: "path-state", id: `path-${n}-state` }),
        el("div", { class: "path-alarm", id: `path-${n}-alarm` }),
        el("div", { class: "buttons" }, button("start", "Cycle start", "go"),
          button("hold", "Feed hold", "hold"), button("reset", "Reset", "")));
    }));
  }
  for (const p of v.paths) {
    const n = p.path_no;
    const card = $(`path-${n}`);
    const cls = `path-card ${p.run_state}${n === state.path ? " shown" : ""}`;
    if (card.className !== cls) card.className = cls;
    setText($(`path-${n}-state`), `${p.mode} ${p.run}  ${oNumber(p.program)} ` +
      `N${p.sequence}  ${count(p.parts, "part")}`);
    setText($(`path-${n}-alarm`), p.alarm ? `ALM ${p.alarm}` : (p.emergency ? "EMG" : "no alarm"));
  }
}

function choosePath(n) {
  if (state.path === n) return;
  state.path = n;
  state.view = null;
  state.dirKey = state.progKey = state.versions = state.paramKey = state.macroKey = null;
  loadParams();
  loadMacros();
  subscribe();
}

function renderMachine(v) {
  if (v.path_no !== state.path) return;  // a frame of the path shown before
  const first = state.view === null;
  state.view = v;
  const shown = v.path_count > 1 ? `  ${v.path_name}` : "";
  $("crumb").textContent = `${v.name}  :${v.port}  (${v.control_class})${shown}`;
  renderPaths(v);
  $("m-mode").textContent = v.mode;
  const run = $("run-state");
  run.textContent = v.run;
  run.className = v.run;
  $("status-table").replaceChildren(el("tr", {}, el("th", {}, "field"), el("th", {}, "value"),
    el("th", {}, "")), ...v.status.map((f) => el("tr", {}, el("td", {}, f.field),
    el("td", {}, `${f.value} ${f.name}`), el("td", {}, el("small", {}, f.meaning)))));

  if (first) {
    $("mode").replaceChildren(...v.modes.map(([n, label]) =>
      el("option", { value: String(n) }, label)));
    $("pmc-area").replaceChildren(...v.pmc_areas.map((a) =>
      el("option", { value: a.area }, `${a.area} (${a.size})`)));
    if (state.pmcArea !== null) $("pmc-area").value = state.pmcArea;
    $("fault-kind").replaceChildren(...v.fault_kinds.map((k) => el("option", { value: k }, k)));
    applyReadOnly();
  }
  // a write from outside (a client, the command line) shows: the lists are read again
  const seen = state.versions;
  state.versions = v.versions;
  if (seen && seen.data !== v.versions.data) loadParams();
  if (seen && seen.macro !== v.versions.macro) loadMacros();
  setIfIdle($("mode"), String(v.panel.mode));
  setIfIdle($("pwe"), v.panel.pwe);
  setIfIdle($("emergency"), v.panel.emergency);
  setIfIdle($("feed-ov"), v.overrides.feed);
  $("feed-ov-text").textContent = `${v.overrides.feed} %`;
  setIfIdle($("rapid-ov"), String(v.overrides.rapid));
  setIfIdle($("spindle-ov"), v.overrides.spindle);
  $("spindle-ov-text").textContent = `${v.overrides.spindle} %`;

  // the kinds as position --kind and watch name them (distance: the distance to go)
  const kinds = ["absolute", "machine", "relative", "distance"];
  $("pos-table").replaceChildren(
    el("tr", {}, el("th", {}, ""), ...kinds.map((k) => el("th", {}, k))),
    ...v.positions.map((p) => el("tr", {}, el("th", {}, p.axis),
      ...kinds.map((k) => el("td", {}, fmt(p[k]))))));
  $("m-feed").textContent = v.feed;
  $("m-spindle").textContent = v.spindle_speed;
  $("m-program").textContent = oNumber(v.program_running);
  $("m-sequence").textContent = v.sequence;
  // each servo load by its axis, as the command line's watch names them
  const axis = (i) => v.positions[i] ? v.positions[i].axis : String(i + 1);
  $("loads").textContent =
    `spindle load ${v.loads.spindle.map((x) => x + " %").join(", ")}` +
    ` | servo load ${v.loads.servo.map((x, i) => `${axis(i)} ${x} %`).join(", ")}`;

  const t = v.timers;
  $("timer-table").replaceChildren(
    el("tr", {}, el("td", {}, "power on"), el("td", {}, clock(t.power_on))),
    el("tr", {}, el("td", {}, "operating"), el("td", {}, clock(t.operating))),
    el("tr", {}, el("td", {}, "cutting"), el("td", {}, clock(t.cutting))),
    el("tr", {}, el("td", {}, "cycle"), el("td", {}, clock(t.cycle))),
    el("tr", {}, el("td", {}, "parts count"), el("td", { id: "parts-count" }, String(v.parts.count))),
    el("tr", {}, el("td", {}, "total parts"), el("td", {}, String(v.parts.total))),
    el("tr", {}, el("td", {}, "parts required"), el("td", {}, String(v.parts.required ?? "-"))));

  $("alarms").replaceChildren(...(v.alarms.length ? v.alarms.map((a) =>
    el("li", { class: "alarm" }, a.text))
    : [el("li", { class: "none" }, "no active alarm")]));
  $("history").replaceChildren(...v.history.map((h) =>
    el("li", {}, `${h.occurred_at} ${h.text}`)));  // as the command line's alarms --history

  const dirKey = JSON.stringify(v.programs);
  if (state.dirKey !== dirKey) {
    state.dirKey = dirKey;
    $("programs").replaceChildren(...v.programs.map((p) =>
      el("li", { class: p.main ? "main" : "" },
        `O${String(p.number).padStart(4, "0")} ${p.name} (${p.size} chars)${p.running ? " - running" : ""}${p.main ? " - main" : ""} `,
        el("button", { class: "small", "data-write": "", disabled: state.readOnly,
          onclick: () => act("select_program", { number: p.number }) }, "select"))));
  }
  const prog = v.program;
  const pre = $("program-text");
  if (prog) {
    const key = `${prog.number}:${prog.lines.length}:${prog.lines.join("\n").length}`;
    if (state.progKey !== key) {
      state.progKey = key;
      pre.replaceChildren(...prog.lines.map((line) => el("span", {}, line + "\n")));
    }
    const want = prog.line ? pre.children[prog.line - 1] : null;
    const cur = pre.querySelector(".cur");
    if (cur !== want) {
      if (cur) cur.className = "";
      if (want) {
        want.className = "cur";
        pre.scrollTop = Math.max(0, want.offsetTop - pre.offsetTop - 60);
      }
    }
  } else {
    state.progKey = null;
    pre.textContent = "no main program";
  }

  $("faults").replaceChildren(...(v.faults.length ? v.faults.map((f) =>
    el("li", {}, `${f.kind} ${f.arg_text}: ${count(f.remaining, "answer")} left`))
    : [el("li", {}, "no fault armed")]));
  plot(v);
}

function plot(v) {
  const c = $("plot"), g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  const pts = v.path;
  if (!pts.length) return;
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (const p of pts) {
    x0 = Math.min(x0, p[0]); x1 = Math.max(x1, p[0]);
    y0 = Math.min(y0, p[1] ?? 0); y1 = Math.max(y1, p[1] ?? 0);
  }
  const pad = 20, w = c.width - 2 * pad, h = c.height - 2 * pad;
  const scale = Math.min(w / Math.max(x1 - x0, 1), h / Math.max(y1 - y0, 1));
  const X = (x) => pad + (x - x0) * scale, Y = (y) => c.height - pad - (y - y0) * scale;
  g.strokeStyle = "#c5ccd6"; g.strokeRect(pad - 4, pad - 4, w + 8, h + 8);
  g.fillStyle = "#6b7480"; g.font = "11px sans-serif";
  g.fillText(`X ${fmt(x0, 1)}..${fmt(x1, 1)}  Y ${fmt(y0, 1)}..${fmt(y1, 1)} mm`, pad, 12);
  g.strokeStyle = "#2563eb"; g.lineWidth = 2; g.beginPath();
  pts.forEach((p, i) => (i ? g.lineTo(X(p[0]), Y(p[1] ?? 0)) : g.moveTo(X(p[0]), Y(p[1] ?? 0))));
  g.stroke();
  const last = pts[pts.length - 1];
  g.fillStyle = "#d0312d"; g.beginPath();
  g.arc(X(last[0]), Y(last[1] ?? 0), 5, 0, 2 * Math.PI); g.fill();
}

function renderPmc(p) {
  const grid = $("pmc-grid");
  if (!p || p.error) {
    $("pmc-note").textContent = p ? p.error : "";
    grid.replaceChildren();
    state.pmcKey = null;
    return;
  }
  if (state.pmcArea === null) {  // the window the server chose: the list shows it
    state.pmcArea = p.area;
    $("pmc-area").value = p.area;
  }
  const forced = p.area === "X" || p.area === "F";
  setText($("pmc-note"), state.pmcError || (p.write_protected && !forced ? "write-protected" :
    (forced ? "bits set as the simulator" : "")));
  const bits = [7, 6, 5, 4, 3, 2, 1, 0];
  const key = `${p.area}:${p.start}:${p.bytes.length}`;
  if (state.pmcKey !== key) {
    state.pmcKey = key;
    const head = el("tr", {}, el("th", {}, "addr"), ...bits.map((b) => el("th", {}, `.${b}`)),
      el("th", {}, "hex"));
    const rows = p.bytes.map((_, i) => {
      const address = p.start + i;
      return el("tr", {}, el("th", {}, `${p.area}${address}`),
        ...bits.map((b) => el("td", {
          class: "bit", id: `pmc-${p.area}${address}-${b}`,
          "data-address": String(address), "data-bit": String(b), "data-write": "",
          onclick: () => state.readOnly ? show("read-only dashboard", false)
            : act("pmc_bit", { area: p.area, address, bit: b }),
        }, "0")),
        el("td", { id: `pmc-${p.area}${address}-hex` }, "00"));
    });
    grid.replaceChildren(head, ...rows);
  }
  p.bytes.forEach((byte, i) => {
    const address = p.start + i;
    for (const b of bits) {
      const cell = $(`pmc-${p.area}${address}-${b}`);
      const on = (byte & (1 << b)) !== 0;
      const cls = on ? "bit on" : "bit";
      if (cell.className !== cls) cell.className = cls;
      setText(cell, on ? "1" : "0");
    }
    setText($(`pmc-${p.area}${address}-hex`), byte.toString(16).padStart(2, "0"));
  });
}

// -- parameters and macros -----------------------------------------------------------------
// A value box shows the machine's value unless the user has typed another there (written or
// not: a refused value stays, with its reason beside it, until it is written or changed).
function valueBox(id, value, attrs) {
  const input = el("input", { value, id, "data-write": "", ...attrs });
  input.dataset.shown = value;
  input.addEventListener("input", () => why(id, ""));
  return input;
}

function refresh(id, value) {
  const input = $(id);
  if (!input) return;
  if (input.value === input.dataset.shown && document.activeElement !== input) input.value = value;
  input.dataset.shown = value;
}

function why(id, text) {
  const note = $(`${id}-why`);
  if (note) setText(note, text);
}

async function writeBox(id, action, args, shown) {
  const body = await act(action, args);
  if (body.ok) {
    const input = $(id);
    if (input) { input.dataset.shown = shown(body); input.value = input.dataset.shown; }
    why(id, "");
  } else {
    why(id, `${body.ew_name ? body.ew_name + " " : ""}${body.error || ""}`);
  }
  return body;
}

function searchNote(id, text, error) {
  const note = $(id);
  setText(note, text);
  note.className = error ? "note error" : "note";
}

async function loadParams() {
  if (state.machine === null) return;
  const q = encodeURIComponent($("param-search").value);
  const answer = await newest("params",
    `/api/machines/${state.machine}/params?q=${q}&path=${state.path}`);
  if (answer === null) return;  // a later search is under way
  const { res, body } = answer;
  if (!res.ok) { searchNote("param-note", body.error, true); return; }
  searchNote("param-note", body.params.length ? "" : "no parameter found", false);
  const key = JSON.stringify(body.params.map((p) => [p.number, p.values.length]));
  if (state.paramKey === key) {  // the same rows: their values, in place
    for (const p of body.params) {
      p.values.forEach((val, i) => refresh(`param-${p.number}-${p.axis ? i + 1 : 0}`, val));
    }
    return;
  }
  state.paramKey = key;
  $("params").replaceChildren(
    el("tr", {}, el("th", {}, "no."), el("th", {}, "name"), el("th", {}, "type"),
      el("th", {}, "value(s)")),
    ...body.params.map((p) => el("tr", {}, el("td", {}, String(p.number)),
      el("td", {}, p.name), el("td", {}, p.type),
      el("td", {}, ...p.values.map((val, i) => {
        const axis = p.axis ? i + 1 : 0;
        const id = `param-${p.number}-${axis}`;
        const input = valueBox(id, val, { disabled: state.readOnly, class: p.bits ? "bits" : "",
          title: p.bits ? "8 bits #7..#0 (10110000), or 0xB0, 0b10110000"
            : `${p.low}..${p.high}` });
        const write = () => writeBox(id, "write_param", { number: p.number, axis,
          value: input.value }, (r) => r.text);
        input.addEventListener("keydown", (ev) => { if (ev.key === "Enter") write(); });
        const save = el("button", { class: "small", id: `param-save-${p.number}-${axis}`,
          "data-write": "", disabled: state.readOnly, onclick: write }, "write");
        const name = p.axis ? [el("b", { class: "axis" }, p.axes[i])] : [];
        return el("div", { class: "value" }, ...name, input, save,
          el("span", { class: "why", id: `${id}-why` }));
      })))));
}

async function loadMacros() {
  if (state.machine === null) return;
  const q = encodeURIComponent($("macro-search").value);
  const answer = await newest("macros",
    `/api/machines/${state.machine}/macros?q=${q}&path=${state.path}`);
  if (answer === null) return;  // a later search is under way
  const { res, body } = answer;
  if (!res.ok) { searchNote("macro-note", body.error, true); return; }
  searchNote("macro-note", body.note || "", false);
  const key = JSON.stringify(body.macros.map((m) => [m.number, m.writable]));
  if (state.macroKey === key) {
    for (const m of body.macros) refresh(`macro-${m.number}`, m.value ?? "");
    return;
  }
  state.macroKey = key;
  $("macros").replaceChildren(
    el("tr", {}, el("th", {}, "#"), el("th", {}, "value")),
    ...body.macros.map((m) => {
      const id = `macro-${m.number}`;
      const input = valueBox(id, m.value ?? "", { placeholder: "vacant",
        disabled: state.readOnly || !m.writable });
      const write = () => writeBox(id, "write_macro", { number: m.number, value: input.value },
        (r) => r.value ?? "");
      input.addEventListener("keydown", (ev) => { if (ev.key === "Enter") write(); });
      const save = el("button", { class: "small", id: `macro-save-${m.number}`, "data-write": "",
        disabled: state.readOnly || !m.writable, onclick: write }, "write");
      return el("tr", {}, el("td", {}, `#${m.number}`),
        el("td", {}, input, save, el("span", { class: "why", id: `${id}-why` })));
    }));
}

// The PMC window: "100" in the chosen area, or "R100" naming the area, as the CLI takes them.
async function pmcFrom() {
  const area = encodeURIComponent($("pmc-area").value || "X");
  const start = encodeURIComponent($("pmc-start").value);
  const res = await fetch(`/api/machines/${state.machine}/pmc?area=${area}&start=${start}`);
  const body = await res.json();
  if (!res.ok) {
    const note = $("pmc-note");
    note.textContent = `${body.ew_name ? body.ew_name + " " : ""}${body.error}`;
    note.className = "error";
    state.pmcError = note.textContent;
    return;
  }
  state.pmcError = "";
  $("pmc-note").className = "";
  state.pmcArea = body.area;
  state.pmcStart = body.start;
  $("pmc-area").value = body.area;
  $("pmc-start").value = String(body.start);
  subscribe();
}

// -- controls ------------------------------------------------------------------------------
function applyReadOnly() {
  document.body.classList.toggle("read-only", state.readOnly);
  $("ro-banner").hidden = !state.readOnly;
  for (const node of document.querySelectorAll("[data-write]")) {
    if ("disabled" in node) node.disabled = state.readOnly;
  }
  faultKindChosen();
}

// What the fault's arg box takes, beside it: a DROP or a SPLIT takes none, so its box is shut
// and nothing of it is sent (the action refuses an arg for them, as sim fault drop --arg does)
const FAULT_ARGS = { DELAY: "milliseconds", ERROR: "EW code, by number or name" };

function faultKindChosen() {
  const kind = $("fault-kind").value;
  const takes = FAULT_ARGS[kind];
  $("fault-arg").disabled = state.readOnly || !takes;
  $("fault-arg-note").textContent = takes ?? (kind ? `${kind} takes no arg` : "");
}

function wire() {
  $("cycle-start").onclick = () => act("cycle", { action: "start" });
  $("feed-hold").onclick = () => act("cycle", { action: "hold" });
  $("reset").onclick = () => act("cycle", { action: "reset" });
  $("mode").onchange = (e) => act("panel", { mode: Number(e.target.value) });
  $("pwe").onchange = (e) => act("panel", { pwe: e.target.checked ? 1 : 0 });
  $("emergency").onchange = (e) => act("panel", { emergency: e.target.checked ? 1 : 0 });
  $("feed-ov").onchange = (e) => act("overrides", { feed: Number(e.target.value) });
  $("rapid-ov").onchange = (e) => act("overrides", { rapid: Number(e.target.value) });
  $("spindle-ov").onchange = (e) => act("overrides", { spindle: Number(e.target.value) });
  $("alarm-raise").onclick = () => act("raise_alarm", {
    alm_type: $("alarm-type").value, alm_no: $("alarm-no").value, msg: $("alarm-msg").value,
    axis_no: $("alarm-axis").value });
  $("alarm-clear").onclick = () => act("clear_alarms", {});
  $("fault-kind").onchange = faultKindChosen;
  $("fault-inject").onclick = () => {
    const kind = $("fault-kind").value;
    const args = { kind, count: $("fault-count").value };
    if (FAULT_ARGS[kind]) args.arg = $("fault-arg").value;
    act("inject_fault", args);
  };
  $("fault-clear").onclick = () => act("clear_faults", {});
  // Enter in a form's box does what its button does, as in the parameter and macro boxes
  const onEnter = (ids, button) => ids.forEach((id) => $(id).addEventListener("keydown",
    (ev) => { if (ev.key === "Enter") $(button).click(); }));
  onEnter(["alarm-type", "alarm-no", "alarm-axis", "alarm-msg"], "alarm-raise");
  onEnter(["fault-count", "fault-arg"], "fault-inject");
  $("clear-path").onclick = () => act("clear_path", {});
  $("pmc-area").onchange = pmcFrom;
  $("pmc-start").onchange = pmcFrom;
  $("pmc-start").addEventListener("keydown", (ev) => { if (ev.key === "Enter") pmcFrom(); });
  $("param-search").oninput = loadParams;
  const unlock = () => act("unlock", { password: $("param-password").value });
  $("param-unlock").onclick = unlock;
  $("param-password").addEventListener("keydown", (ev) => { if (ev.key === "Enter") unlock(); });
  $("macro-search").oninput = loadMacros;
  $("fleet-filter").oninput = () =>
    newest("fleet", "/api/fleet").then((answer) => answer && renderFleet(answer.body));
  window.addEventListener("hashchange", route);
}

async function main() {
  const info = await (await fetch("/api/info")).json();
  state.readOnly = info.read_only;
  state.machines = info.machines;
  applyReadOnly();
  wire();
  route();
  connect();
}

main();

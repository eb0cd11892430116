// MultiBots viewer: the page. Replay mode plays chunks fetched on demand; live mode shows
// the frames the server streams and sends it pause / resume / step / speed.
import { Renderer, stateName, formatT, setNames } from "./draw.js";
import { ReplaySource, LiveSource, setCodec, setEventNames, stateCode, isMarked, headingAngle, queuesAt } from "./data.js";

const params = new URLSearchParams(location.search);
const RENDER = params.get("render") === "1";
const SPS = 30;  // steps per second at 1x
const SPEEDS = [0.25, 0.5, 1, 2, 4, 8, 16, 32, 64];
const $ = (id) => document.getElementById(id);

const app = {
  meta: null, mode: null, source: null, renderer: null,
  pos: 0, last: 0, playing: false, speed: 1,
  selected: -1, route: null, panel: null, panelFrame: -1, panelBusy: false, panelAt: 0,
  dirty: true, blink: true, lastNow: 0, scrubbing: false,
  drawn: 0, drawTimes: [], drawMs: 0, frameTimes: [],
  shown: null,   // what was drawn last: {frame, info}
  y2026: false,  // a League of Robot Runners 2026 replay: footprints and delays (docs/lorr.md)
  error: null,
};

function setText(id, value) {
  const el = $(id);
  if (el && el.textContent !== value) el.textContent = value;
}

function status(msg) { setText("status", msg || ""); }

// ------------------------------------------------------------------ frame selection
/** The resources' queues in frame f (docs/viewer.md): {resources, counts, bottleneck, line,
 * final}. A replay has its run's report and each queue frame by frame; a live run sends the
 * report so far and the queues now with every frame. Null where the run reports none. */
function queuesOf(f) {
  // Grid replays and the original rules report no resources: nothing to show.
  const none = (r) => !r.resources || (!r.resources.length && !r.bottleneck);
  if (app.mode === "replay") {
    const m = app.meta;
    if (none(m)) return null;
    return { resources: m.resources, counts: queuesAt(m.queues, f), bottleneck: m.bottleneck,
      line: m.bottleneck_line, final: true };
  }
  const L = app.source.latest;
  if (!L || none(L.msg)) return null;
  return { resources: L.msg.resources, counts: L.msg.queue, bottleneck: L.msg.bottleneck,
    line: L.msg.bottleneck_line, final: !!L.msg.done };
}

function currentView() {
  const r = app.renderer;
  if (app.mode === "replay") {
    const f = Math.floor(app.pos);
    const frame = app.source.frame(f);
    if (!frame) return null;
    let next = null, alpha = 0;
    if (app.playing && app.speed <= 2 && f < app.last) {
      next = app.source.frame(f + 1);
      alpha = next ? app.pos - f : 0;
    }
    const s = app.meta.summary || {};
    return {
      frame,
      info: {
        cells: app.source.cells(f), goals: app.source.goals(f), last: app.last, T: s.T, done: f === app.last,
        outcome: s.outcome, goodsTotal: app.meta.goods_total, selected: app.selected,
        route: app.route, blinkOn: app.blink, next, alpha, zones: app.zones, queues: queuesOf(f),
      },
    };
  }
  const L = app.source.latest;
  if (!L) return null;
  return {
    frame: L.frame,
    info: {
      cells: L.cells, last: null, T: L.msg.T, done: L.msg.done, outcome: L.msg.outcome,
      goodsTotal: L.msg.goods_total, selected: app.selected, route: app.route, blinkOn: app.blink,
      zones: app.zones, queues: queuesOf(L.frame.step),
    },
  };
}

function drawNow() {
  const v = currentView();
  const t0 = performance.now();
  if (!v) {  // its chunk is on its way: keep the last picture meanwhile
    if (!app.shown) app.renderer.draw(null, { cells: app.meta.cells_full });
    status("loading\u2026");
    return false;
  }
  if (app.mode === "replay" && !app.playing && !app.source.failed) status("");
  app.renderer.draw(v.frame, v.info);
  app.shown = v;
  const t1 = performance.now();
  app.drawn++;
  app.drawTimes.push(t1 - t0);
  if (app.drawTimes.length > 120) app.drawTimes.shift();
  app.frameTimes.push(t1);
  while (app.frameTimes.length && app.frameTimes[0] < t1 - 1000) app.frameTimes.shift();
  updateDom(v);
  return true;
}

/** Deliveries per window as bars, the current window marked (the throughput over time). */
function drawFlow(windows, window, step) {
  const box = $("flow");
  if (!windows || windows.length === 0) { box.hidden = true; return; }
  box.hidden = false;
  setText("flow-window", window.toLocaleString("en"));
  const key = `${windows.length}:${Math.floor(step / window)}:${windows[windows.length - 1]}`;
  if (box.dataset.key === key) return;
  box.dataset.key = key;
  const svg = $("flow-bars");
  const top = Math.max(...windows, 1);
  const w = 200 / windows.length;
  const current = Math.floor(step / window);
  svg.innerHTML = windows.map((d, k) => {
    const h = 38 * d / top;
    const fill = k === current ? "#ffbf00" : "#1f77b4";
    return `<rect x="${(k * w).toFixed(2)}" y="${(40 - h).toFixed(2)}" width="${Math.max(w - 0.5, 0.5).toFixed(2)}" height="${h.toFixed(2)}" fill="${fill}"><title>${k * window}..${(k + 1) * window}: ${d}</title></rect>`;
  }).join("");
}

/** The bottleneck line and the queues now, beside the map. */
function drawQueues(q) {
  const box = $("queues-box");
  if (!q) { box.hidden = true; return; }
  box.hidden = false;
  setText("bottleneck-head", q.final ? "bottleneck" : "bottleneck so far");
  setText("bottleneck-line", q.line || (q.final ? "none: no resource held the fleet up"
    : "none yet"));
  const rows = q.resources.map((u, j) => [u, q.counts[j]]).filter(([, c]) => c > 0)
    .sort((a, b) => b[1] - a[1] || a[0].node.localeCompare(b[0].node));
  const key = rows.map(([u, c]) => `${u.kind} ${u.node} ${c}`).join("|");
  const list = $("queue-list");
  if (list.dataset.key === key) return;
  list.dataset.key = key;
  list.replaceChildren(...rows.map(([u, c]) => {
    const dt = document.createElement("dt");
    dt.textContent = `${u.kind} ${u.node}`;
    const dd = document.createElement("dd");
    dd.textContent = String(c);
    dd.dataset.node = u.node; dd.dataset.kind = u.kind;
    return [dt, dd];
  }).flat());
  setText("queue-none", rows.length ? "" : "no robot queued now");
}

function updateDom(v) {
  const { frame, info } = v;
  drawQueues(info.queues);
  if (app.mode === "replay") {
    const s = app.meta.summary || {};
    drawFlow(s.windows, s.window || 1000, frame.step);
  } else if (app.source.latest) {
    drawFlow(app.source.latest.msg.windows, app.source.latest.msg.window || 1000, frame.step);
  }
  setText("c-step", info.last !== null && info.last !== undefined ? `${frame.step} / ${info.last}` : String(frame.step));
  setText("c-S", String(frame.S));
  setText("c-C", String(frame.C));
  // A grid replay (docs/lorr.md) counts tasks finished; its pool has no total.
  setText("c-delivered", app.meta.layout.grid ? String(frame.delivered) : `${frame.delivered} / ${info.goodsTotal}`);
  setText("c-T", formatT(info));
  const tl = $("timeline");
  if (app.mode === "replay") {
    if (!app.scrubbing && Number(tl.value) !== frame.step) tl.value = String(frame.step);
  } else {
    tl.max = String(frame.step); tl.value = String(frame.step);
  }
  const playing = app.mode === "replay" ? app.playing : !(app.source.latest && app.source.latest.msg.paused);
  setText("btn-play", playing ? "\u275a\u275a pause" : "\u25b6 play");
  if (app.mode === "live" && app.source.latest) {
    const m = app.source.latest.msg;
    if (m.speed !== app.speed && SPEEDS.includes(m.speed)) { app.speed = m.speed; $("speed").value = String(m.speed); }
    if (m.error) status(m.error);
    else if (!app.source.connected && !m.done) status("connection lost: retrying");
    else status(m.done ? (m.T === null ? "run ended: incomplete" : "run complete") : (m.paused ? "paused" : ""));
  }
}

// ------------------------------------------------------------------ playback (replay)
function seek(f) {
  app.pos = Math.max(0, Math.min(app.last, Math.round(f)));
  app.dirty = true;
  const i = app.source.chunkIndex(Math.floor(app.pos));
  return app.source.load(i).then(() => { app.dirty = true; });
}

function play() {
  if (app.mode === "live") { app.source.control("resume").catch(() => {}); return; }
  if (app.pos >= app.last) app.pos = 0;
  app.playing = true; app.dirty = true;
}

function pause() {
  if (app.mode === "live") { app.source.control("pause").catch(() => {}); return; }
  app.playing = false; app.pos = Math.floor(app.pos); app.dirty = true;
}

function togglePlay() {
  if (app.mode === "live") {
    const L = app.source.latest;
    if (L && L.msg.paused) play(); else pause();
  } else if (app.playing) pause(); else play();
}

function stepBy(k) {
  if (app.mode === "live") { if (k > 0) app.source.control("step").catch(() => {}); return; }
  app.playing = false;
  seek(Math.floor(app.pos) + k);
}

function setSpeed(s) {
  s = Number(s);
  if (!SPEEDS.includes(s)) return;
  app.speed = s;
  $("speed").value = String(s);
  if (app.mode === "live") app.source.control("speed", s).catch(() => {});
}

function tick(now) {
  requestAnimationFrame(tick);
  const dt = app.lastNow ? Math.min(0.25, (now - app.lastNow) / 1000) : 0;
  app.lastNow = now;
  const blink = Math.floor(now / 400) % 2 === 0;
  if (blink !== app.blink) { app.blink = blink; app.dirty = true; }
  if (app.mode === "replay" && app.playing) {
    const target = Math.min(app.last, app.pos + dt * app.speed * SPS);
    const ci = app.source.chunkIndex(Math.floor(target));
    if (app.source.has(ci)) {
      app.pos = target;
      status("");
    } else {
      app.source.load(ci).catch(() => {});
      status("loading\u2026");
    }
    for (let k = 1; k <= 2; k++) app.source.load(ci + k).catch(() => {});
    if (app.pos >= app.last) { app.pos = app.last; app.playing = false; }
    app.dirty = true;
  }
  if (app.source.failed) status(app.source.failed);
  if (app.dirty) {
    if (drawNow()) app.dirty = false;
  }
  refreshPanel(now);
}

// ------------------------------------------------------------------ robot panel
function select(i) {
  app.selected = i;
  app.route = null;
  app.panel = null;
  app.panelFrame = -1;
  $("panel").hidden = i < 0;
  if (i >= 0) {
    setText("p-title", `robot ${i}`);
    ["p-state", "p-energy", "p-task", "p-S", "p-C"].forEach((id) => setText(id, "\u2026"));
  }
  app.dirty = true;
  refreshPanel(performance.now(), true);
}

function currentStep() {
  if (app.mode === "replay") return Math.floor(app.pos);
  return app.source.latest ? app.source.latest.frame.step : 0;
}

function refreshPanel(now, force = false) {
  if (app.selected < 0 || app.panelBusy) return;
  const f = currentStep();
  if (!force && (f === app.panelFrame || now - app.panelAt < 250)) return;
  app.panelBusy = true; app.panelAt = now;
  const id = app.selected;
  const q = app.mode === "replay" ? `id=${id}&frame=${f}` : `id=${id}`;
  fetch(`/api/robot?${q}`).then((r) => (r.ok ? r.json() : Promise.reject(new Error(`HTTP ${r.status}`))))
    .then((p) => {
      if (app.selected !== id) return;
      app.panel = p; app.panelFrame = f; app.route = p.route; app.dirty = true;
      // Under the 2026 rules the marked bit says "held by a delay" (docs/lorr.md).
      const mark = !p.marked ? "" : (!app.y2026 ? " \u00b7 to charge"
        : ` \u00b7 delayed${p.held_until === null || p.held_until === undefined ? "" : ` until tick ${p.held_until}`}`);
      setText("p-state", stateName(p.state) + mark);
      setText("p-energy", `${p.energy.toFixed(3)} / ${p.energy_full}`);
      setText("p-task", p.task_cell === null ? "\u2014" : String(p.task_cell));
      setText("p-S", String(p.S));
      setText("p-C", String(p.C));
      $("panel").dataset.frame = String(p.frame);
    })
    .catch(() => {})
    .finally(() => { app.panelBusy = false; });
}

// ------------------------------------------------------------------ page wiring
function setupPage() {
  const canvas = $("view"), stage = $("stage");
  const resize = () => {
    app.renderer.resize(stage.clientWidth, stage.clientHeight, window.devicePixelRatio || 1);
    app.dirty = true;
  };
  new ResizeObserver(resize).observe(stage);
  resize();

  let down = null;
  canvas.addEventListener("pointerdown", (e) => {
    down = { x: e.clientX, y: e.clientY, moved: false };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!down) return;
    const dx = e.clientX - down.x, dy = e.clientY - down.y;
    if (!down.moved && Math.hypot(dx, dy) > 4) { down.moved = true; canvas.classList.add("dragging"); }
    if (down.moved) {
      app.renderer.pan(dx, dy); down.x = e.clientX; down.y = e.clientY; app.dirty = true;
    }
  });
  canvas.addEventListener("pointerup", (e) => {
    const wasDrag = down && down.moved;
    down = null; canvas.classList.remove("dragging");
    if (wasDrag) return;
    const rect = canvas.getBoundingClientRect();
    const hit = app.renderer.hitTest(app.shown && app.shown.frame, e.clientX - rect.left, e.clientY - rect.top);
    select(hit);
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const rect = canvas.getBoundingClientRect();
    app.renderer.zoomAt(Math.exp(-e.deltaY * 0.0015), e.clientX - rect.left, e.clientY - rect.top);
    app.dirty = true;
  }, { passive: false });
  canvas.addEventListener("dblclick", () => { app.renderer.resetView(); app.dirty = true; });

  $("btn-play").addEventListener("click", togglePlay);
  $("btn-step").addEventListener("click", () => stepBy(1));
  $("btn-back").addEventListener("click", () => stepBy(-1));
  $("speed").addEventListener("change", (e) => setSpeed(e.target.value));
  $("p-close").addEventListener("click", () => select(-1));
  const tl = $("timeline");
  tl.addEventListener("input", () => { app.scrubbing = true; seek(Number(tl.value)); });
  tl.addEventListener("change", () => { app.scrubbing = false; });
  // space always means play / pause, also while a button has the focus (no double toggle)
  window.addEventListener("keyup", (e) => { if (e.key === " " && e.target.tagName === "BUTTON") e.preventDefault(); }, true);
  window.addEventListener("keydown", (e) => {
    if (e.target && (e.target.tagName === "INPUT" || e.target.tagName === "SELECT")) return;
    if (e.key === " ") { e.preventDefault(); togglePlay(); }
    else if (e.key === "ArrowRight") stepBy(1);
    else if (e.key === "ArrowLeft") stepBy(-1);
    else if (e.key === "+" || e.key === "=") setSpeed(SPEEDS[Math.min(SPEEDS.length - 1, SPEEDS.indexOf(app.speed) + 1)]);
    else if (e.key === "-") setSpeed(SPEEDS[Math.max(0, SPEEDS.indexOf(app.speed) - 1)]);
    else if (e.key === "Escape") select(-1);
    else if (e.key === "z") { app.zones = !app.zones; drawNow(); }
  });

  if (app.mode === "live") {
    $("btn-back").disabled = true;
    tl.disabled = true;
  } else {
    tl.max = String(app.last);
  }
  requestAnimationFrame(tick);
}

// ------------------------------------------------------------------ export (render mode)
function setupRender() {
  document.body.classList.add("render");
  app.renderer.resize(0, 0, 1);
}

async function renderFrame(f, blinkOn) {
  const frame = await app.source.frameAsync(f);
  const s = app.meta.summary || {};
  const info = {
    cells: app.source.cells(f), goals: app.source.goals(f), last: app.last, T: s.T, done: f === app.last,
    outcome: s.outcome, goodsTotal: app.meta.goods_total, selected: -1, route: null, blinkOn: blinkOn !== false,
    queues: queuesOf(f),
  };
  app.renderer.draw(frame, info);
  app.shown = { frame, info };
}

// ------------------------------------------------------------------ hooks for tests and export
function exposeHooks() {
  window.mbViewer = {
    ready: true,
    mode: app.mode,
    meta: () => app.meta,
    state: () => {
      const v = app.shown;
      return {
        frame: v ? v.frame.step : null, last: app.mode === "replay" ? app.last : null,
        playing: app.mode === "replay" ? app.playing : !!(app.source.latest && !app.source.latest.msg.paused),
        speed: app.speed, S: v ? v.frame.S : null, C: v ? v.frame.C : null,
        delivered: v ? v.frame.delivered : null, done: v ? !!v.info.done : false,
        T: v && v.info.done ? v.info.T : null, selected: app.selected,
        panelFrame: app.panel ? app.panel.frame : null, drawn: app.drawn,
        routePoints: app.route ? app.route.length : 0,
        paused: app.mode === "live" ? !!(app.source.latest && app.source.latest.msg.paused) : !app.playing,
        version: app.mode === "live" && app.source.latest ? app.source.latest.msg.version : null,
      };
    },
    // The queue badges drawn last, in client px: {node, kind, count, x, y, w, h}.
    badges: () => {
      const rect = $("view").getBoundingClientRect();
      return app.renderer.badges.map((b) => ({ ...b, x: rect.left + b.x, y: rect.top + b.y }));
    },
    robot: (i) => {
      const v = app.shown;
      if (!v) return null;
      const fr = v.frame;
      const xs = app.renderer.lastXs || fr.x, ys = app.renderer.lastYs || fr.y;
      // side: a 2026 robot's square (agentSize cells, in world px), centred at x, y; else 0.
      return { x: xs[i], y: ys[i], state: stateCode(fr.state[i]), marked: isMarked(fr.state[i]),
        heading: headingAngle(fr.heading[i]), radius: app.meta.radius[i], side: app.renderer.side };
    },
    // The legend's labels, in the order drawn.
    legend: () => app.renderer.legendItems.map((e) => e.it[2]),
    worldToClient: (x, y) => {
      const rect = $("view").getBoundingClientRect();
      const [sx, sy] = app.renderer.toScreen(x, y);
      return { x: rect.left + sx, y: rect.top + sy, scale: app.renderer.scale };
    },
    seek: async (f) => { app.playing = false; await seek(f); drawNow(); app.dirty = false; return app.shown.frame.step; },
    play, pause, setSpeed,
    stats: () => {
      const n = app.drawTimes.length;
      return { fps: app.frameTimes.length, drawMs: n ? app.drawTimes.reduce((a, b) => a + b, 0) / n : 0, drawn: app.drawn };
    },
    size: () => ({ width: app.renderer.canvas.width, height: app.renderer.canvas.height }),
    renderFrame,
    renderFrames: async (frames, blinkEvery) => {
      const out = [];
      for (const f of frames) {
        const on = !blinkEvery || Math.floor(f / blinkEvery) % 2 === 0;
        await renderFrame(f, on);
        out.push(app.renderer.canvas.toDataURL("image/png"));
      }
      return out;
    },
  };
}

async function main() {
  try {
    const r = await fetch("/api/meta");
    if (!r.ok) throw new Error(`HTTP ${r.status}`);
    app.meta = await r.json();
    setCodec(app.meta.codec);
  } catch (err) {
    status(`cannot load the run: ${err}`);
    return;
  }
  const meta = app.meta;
  setNames(meta.state_names);
  setEventNames(meta.event_names);
  app.mode = meta.mode;
  const title = `MultiBots \u00b7 ${meta.name || meta.layout.name}`;
  document.title = title;
  setText("mode", meta.mode);
  $("mode").classList.toggle("live", meta.mode === "live");
  setText("name", `${meta.name || ""} \u00b7 layout ${meta.layout.name} \u00b7 ${meta.robots} robots`);
  if (meta.scenario) { $("scenario-box").hidden = false; setText("scenario", meta.scenario); }
  if (meta.layout.grid) {  // a League of Robot Runners replay (docs/lorr.md): what its counters count
    for (const [id, label, hint] of [["c-S", "errors", "refused joint actions"],
      ["c-delivered", "finished", "tasks finished: the score"]]) {
      const dt = $(id).previousElementSibling;
      dt.textContent = label; dt.title = hint;
    }
    // No charging and no task time under these rules: rows that would mean nothing are gone;
    // under the 2026 rules C counts the delays drawn (the robot's own in its panel).
    app.y2026 = !!meta.lorr && meta.lorr.rules === "2026";
    const gone = app.y2026 ? ["c-T", "p-C", "p-energy"] : ["c-C", "c-T"];
    for (const id of gone) {
      $(id).hidden = true;
      $(id).previousElementSibling.hidden = true;
    }
    if (app.y2026) {
      for (const [id, label, hint] of [["c-C", "delays", "delays drawn so far"],
        ["p-S", "delays", "delays drawn for this robot so far"]]) {
        const dt = $(id).previousElementSibling;
        dt.textContent = label; dt.title = hint;
      }
    }
  }
  const scale = Math.min(8, Math.max(0.1, Number(params.get("scale")) || 1));
  app.renderer = new Renderer($("view"), meta, RENDER ? { fixedScale: scale, title } : { title });
  if (meta.mode === "replay") {
    app.source = new ReplaySource(meta);
    app.last = meta.frames - 1;
    app.pos = Math.min(app.last, Math.max(0, Number(params.get("frame")) || 0));
    await app.source.load(app.source.chunkIndex(Math.floor(app.pos))).catch((e) => status(String(e)));
  } else {
    app.source = new LiveSource(meta, () => { app.dirty = true; });
  }
  const sp = Number(params.get("speed"));
  if (SPEEDS.includes(sp)) { app.speed = sp; $("speed").value = String(sp); }
  if (RENDER) setupRender(); else setupPage();
  exposeHooks();
  if (!RENDER && app.mode === "replay" && params.get("play") === "1") play();
}

main();

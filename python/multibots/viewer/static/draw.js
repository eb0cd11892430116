// MultiBots viewer: drawing. Everything comes from the layout JSON and the frame arrays;
// the page and `multibots render` both draw with this file, so they look the same.

import { CODEC, energyFraction, stateCode } from "./data.js";

// State names come from the engine, through the server's meta (`state_names`): see setNames.
export let STATE_NAMES = [];

export const COLOURS = {
  blue: "#1f77b4",      // on the way to pick up, loading
  red: "#d62728",       // carrying, unloading
  green: "#2ca02c",     // idle, to charger, charging, home, parked
  grey: "#8c8c8c",      // stranded
  other: "#c51b8a",     // a state this viewer does not know
  cellFull: "#d62728",
  cellEmpty: "#111111",
  batteryOk: "#2ca02c",
  batteryLow: "#ff8c00",
  batteryCritical: "#d62728",
  batteryBack: "#2b2b2b",
  floor: "#ffffff",
  backdrop: "#f1f1ec",
  wall: "#1b1b1b",
  highway: "#8a939c",
  departure: "#1f4e9c",
  unloading: "#6a2c91",
  charger: "#ffd23f",
  chargerEdge: "#6b5200",
  banner: "#20242a",
  bannerText: "#ffffff",
  select: "#ffbf00",
  person: "#2b6cb0",          // people on the floor, seen from above: shoulders
  personHead: "#f2c9a0",
  personEdge: "#10243e",
  zoneProtective: "#c81e1e",  // a robot's zones around people (the z key)
  zoneWarning: "#e6a000",
  queue: "#e65100",           // a resource's queue: a badge with its robots
  queueText: "#ffffff",
  bottleneck: "#e6007e",      // the run's bottleneck: a ring around it
  delay: "#9467bd",           // a robot held by a delay (LoRR 2026): outline and pause mark
  delayMark: "#ffffff",
};

const GROUP_COLOURS = [COLOURS.blue, COLOURS.red, COLOURS.green, COLOURS.grey, COLOURS.other];
// state name -> colour group: blue fetching, red carrying, green resting, grey stranded.
const GROUP_OF_NAME = {
  IDLE: 2, TO_PICKUP: 0, LOADING: 0, TO_DROP: 1, UNLOADING: 1, TO_CHARGER: 2, CHARGING: 2,
  TO_HOME: 2, PARKED: 2, STRANDED: 3, WAIT_CHARGER: 2,
};
// state code -> colour group (codes of unknown names stay "other"), one entry per code the
// state byte can hold
let STATE_GROUP = new Uint8Array(0);

/** Takes the engine's state names (`meta.state_names`, indexed by code); after setCodec. */
export function setNames(stateNames) {
  STATE_NAMES = Array.from(stateNames || []);
  STATE_GROUP = new Uint8Array(CODEC.stateMask + 1).fill(4);
  STATE_NAMES.forEach((name, code) => { if (name in GROUP_OF_NAME) STATE_GROUP[code] = GROUP_OF_NAME[name]; });
}

/** The colour and the name of a state byte (or a state code). */
export function stateColour(b) { return GROUP_COLOURS[STATE_GROUP[stateCode(b)]]; }
export function stateName(b) { return STATE_NAMES[stateCode(b)] || `STATE_${stateCode(b)}`; }

const FONT = '"DejaVu Sans", "Liberation Sans", Arial, sans-serif';
const TAU = Math.PI * 2;

export class Renderer {
  /**
   * @param canvas  the canvas to draw on
   * @param meta    /api/meta: layout, robots, radius, energy_full, threshold, goods_total
   * @param opts    {fixedScale: world px -> canvas px (export), title}
   */
  constructor(canvas, meta, opts = {}) {
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d", { alpha: false });
    this.meta = meta;
    this.layout = meta.layout;
    // A League of Robot Runners grid (docs/lorr.md): {rows, cols, cells: ["..@.", ...]}.
    this.grid = meta.layout.grid || null;
    // The League of Robot Runners' 2026 rules (docs/lorr.md): robots are squares of side
    // agentSize cells, and the marked bit of the state byte says "held by a delay".
    const lorr = meta.lorr || {};
    this.y2026 = !!this.grid && lorr.rules === "2026";
    const size = Number(lorr.agentSize);
    this.side = this.y2026 ? (Number.isFinite(size) && size > 0 ? size : 1) * (meta.layout.cell_size || 16) : 0;
    this.n = meta.robots;
    // People on the floor (docs/people.md): {count, radius, zones: [protective, warning]}.
    this.humans = meta.humans || null;
    this.radius = Float64Array.from(meta.radius);
    this.maxRadius = this.radius.reduce((a, b) => Math.max(a, b), 0);
    this.thrFrac = meta.threshold / meta.energy_full;
    this.lowFrac = (1 + this.thrFrac) / 2;
    this.fixedScale = opts.fixedScale || 0;
    this.title = opts.title || "";
    this.ui = this.fixedScale ? Math.max(1, this.fixedScale) : 1;
    this.zoom = 1; this.panX = 0; this.panY = 0;
    this.bg = document.createElement("canvas");
    this.cellLayer = document.createElement("canvas");  // cells only, transparent elsewhere
    this.bgValid = false;
    this.cellsDrawn = null;
    this._world();
    this._indexCells();
    this.groups = new Int32Array(this.n);
    this.groupCount = new Int32Array(GROUP_COLOURS.length);
    // Resources go by their node's name (docs/metrics.md); the chargers' queue by "chargers".
    this.nodeOf = new Map((meta.layout.nodes || []).map((nd, k) => [nd.name, k]));
    this.badges = [];  // the queue badges drawn last: {node, count, x, y, w, h} in css px
  }

  // --------------------------------------------------------------- geometry
  _world() {
    const L = this.layout;
    const b = L.bounds;
    let x0 = b[0], y0 = b[1], x1 = b[2], y1 = b[3];
    const aisle = L.aisle_width || 50;
    const cell = L.cell_size || 50;
    this.aisle = aisle; this.cell = cell;
    for (const nd of L.nodes) {
      const pad = nd.kind === "charger" ? aisle * 0.45 : 0;
      x0 = Math.min(x0, nd.x - pad); x1 = Math.max(x1, nd.x + pad);
      y0 = Math.min(y0, nd.y - pad); y1 = Math.max(y1, nd.y + pad);
    }
    for (const c of L.cells) {
      x0 = Math.min(x0, c.x); y0 = Math.min(y0, c.y);
      x1 = Math.max(x1, c.x + c.w); y1 = Math.max(y1, c.y + c.h);
    }
    // delivered goods: small squares in rows below the warehouse
    this.goodsSize = cell * 0.22;
    this.goodsGap = this.goodsSize * 0.45;
    this.goodsTop = Math.max(b[3], y1) + cell * 0.3;
    this.goodsLabel = cell * 0.26;
    const pitch = this.goodsSize + this.goodsGap;
    this.goodsRows = 2;
    const margin = Math.max(this.maxRadius * 1.5, aisle * 0.3);
    this.wx0 = x0 - margin;
    this.wx1 = x1 + margin;
    this.wy0 = y0 - margin;
    this.wy1 = this.goodsTop + this.goodsRows * pitch + margin * 0.6;
    this.goodsX0 = b[0];
    this.goodsPerRow = Math.max(1, Math.floor((b[2] - b[0] - cell * 1.9 + this.goodsGap) / pitch));
  }

  /** A bucket grid of the cells, to find the neighbours of a cell quickly. */
  _indexCells() {
    const cells = this.layout.cells;
    let size = 1;
    for (const c of cells) size = Math.max(size, c.w, c.h);
    this.bucket = size * 2;
    this.buckets = new Map();
    for (let k = 0; k < cells.length; k++) {
      const c = cells[k];
      for (let gx = Math.floor(c.x / this.bucket); gx <= Math.floor((c.x + c.w) / this.bucket); gx++) {
        for (let gy = Math.floor(c.y / this.bucket); gy <= Math.floor((c.y + c.h) / this.bucket); gy++) {
          const key = gx * 1e6 + gy;
          if (!this.buckets.has(key)) this.buckets.set(key, []);
          this.buckets.get(key).push(k);
        }
      }
    }
  }

  _cellsNear(x0, y0, x1, y1) {
    const out = new Set();
    for (let gx = Math.floor(x0 / this.bucket); gx <= Math.floor(x1 / this.bucket); gx++) {
      for (let gy = Math.floor(y0 / this.bucket); gy <= Math.floor(y1 / this.bucket); gy++) {
        const list = this.buckets.get(gx * 1e6 + gy);
        if (list) for (const k of list) out.add(k);
      }
    }
    const cells = this.layout.cells;
    return [...out].map((k) => cells[k]).filter((c) => c.x <= x1 && c.x + c.w >= x0 && c.y <= y1 && c.y + c.h >= y0);
  }

  /** Size the canvas. Page: css size of its box and devicePixelRatio. Export: fixed scale. */
  resize(cssW, cssH, dpr = 1) {
    const ui = this.ui;
    this.bannerH = Math.round(30 * ui);
    this.dpr = dpr;
    const ww = this.wx1 - this.wx0, wh = this.wy1 - this.wy0;
    if (this.fixedScale) {
      cssW = Math.round(ww * this.fixedScale);
      this._legendLayout(cssW);
      cssH = Math.round(wh * this.fixedScale) + this.bannerH + this.legendH;
      cssW += cssW % 2; cssH += cssH % 2;  // video encoders want even sizes
      this._legendLayout(cssW);
    } else {
      this._legendLayout(cssW);
    }
    this.cssW = cssW; this.cssH = cssH;
    this.canvas.width = Math.max(1, Math.round(cssW * dpr));
    this.canvas.height = Math.max(1, Math.round(cssH * dpr));
    if (this.fixedScale) {
      this.canvas.style.width = cssW + "px";
      this.canvas.style.height = cssH + "px";
    }
    this.bg.width = this.canvas.width; this.bg.height = this.canvas.height;
    this.cellLayer.width = this.canvas.width; this.cellLayer.height = this.canvas.height;
    const areaH = cssH - this.bannerH - this.legendH;
    this.areaTop = this.bannerH; this.areaH = areaH;
    const fit = this.fixedScale || Math.max(1e-6, Math.min(cssW / ww, areaH / wh));
    this.fit = fit;
    this.baseOx = (cssW - ww * fit) / 2 - this.wx0 * fit;
    this.baseOy = this.bannerH + (areaH - wh * fit) / 2 - this.wy0 * fit;
    this.bgValid = false;
  }

  get scale() { return this.fit * this.zoom; }
  get ox() { return this.baseOx + this.panX; }
  get oy() { return this.baseOy + this.panY; }

  toScreen(x, y) { return [this.ox + x * this.scale, this.oy + y * this.scale]; }
  toWorld(sx, sy) { return [(sx - this.ox) / this.scale, (sy - this.oy) / this.scale]; }

  zoomAt(factor, sx, sy) {
    const [wx, wy] = this.toWorld(sx, sy);
    this.zoom = Math.min(64, Math.max(0.25, this.zoom * factor));
    const [nx, ny] = this.toScreen(wx, wy);
    this.panX += sx - nx; this.panY += sy - ny;
    this.bgValid = false;
  }
  pan(dx, dy) { this.panX += dx; this.panY += dy; this.bgValid = false; }
  resetView() { this.zoom = 1; this.panX = 0; this.panY = 0; this.bgValid = false; }

  _worldTransform(ctx) {
    const d = this.dpr, s = this.scale;
    ctx.setTransform(d * s, 0, 0, d * s, d * this.ox, d * this.oy);
  }

  /** Index of the robot under css point (sx, sy), or -1. */
  hitTest(frame, sx, sy) {
    if (!frame) return -1;
    const [wx, wy] = this.toWorld(sx, sy);
    const slack = 4 / this.scale;
    let best = -1, bestD = Infinity;
    const half = this.side / 2;
    for (let i = 0; i < this.n; i++) {
      const dx = frame.x[i] - wx, dy = frame.y[i] - wy;
      const d = Math.hypot(dx, dy);
      // a 2026 robot is its square; any other a disc
      const inside = this.side ? Math.max(Math.abs(dx), Math.abs(dy)) <= half + slack : d <= this.radius[i] + slack;
      if (inside && d < bestD) { best = i; bestD = d; }
    }
    return best;
  }

  // --------------------------------------------------------------- background
  _legendItems() {
    if (this.grid) {
      // 2026: each robot is its square (agentSize), and a robot held by a delay is marked.
      const robot = this.y2026 ? "square" : "robot";
      return [
        [robot, COLOURS.blue, "to an errand"],
        [robot, COLOURS.red, "to its task's last errand"],
        [robot, COLOURS.green, "no goal"],
        ...(this.y2026 ? [["delay", COLOURS.delay, "held by a delay"]] : []),
        ["cell", COLOURS.blue, "goal (robot's colour)"],
        ["cell", COLOURS.wall, "obstacle"],
      ];
    }
    return [
      ["robot", COLOURS.blue, "to pick up, loading"],
      ["robot", COLOURS.red, "carrying, unloading"],
      ["robot", COLOURS.green, "idle, charging, home"],
      ["robot", COLOURS.grey, "stranded"],
      ["cell", COLOURS.cellFull, "goods"],
      ["cell", COLOURS.cellEmpty, "empty cell"],
      ["departure", COLOURS.departure, "departure"],
      ["unloading", COLOURS.unloading, "unloading"],
      ["charger", COLOURS.charger, "charger"],
      ["battery", null, "battery (blinks: to charge)"],
      // People only when the run has them (docs/people.md); their zones are drawn with z.
      ...(this.humans ? [["person", COLOURS.person, "person"],
                         ["zones", null, "robot's protective, warning zone (z)"]] : []),
      // Queues and the bottleneck where the run reports resources (a live run always does).
      ...(this.meta.mode === "live" || (this.meta.resources || []).length
        ? [["queue", COLOURS.queue, "robots queued"], ["bottleneck", COLOURS.bottleneck, "bottleneck"]] : []),
    ];
  }

  _legendLayout(cssW) {
    const ui = this.ui, ctx = this.ctx;
    ctx.save();
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.font = `${12 * ui}px ${FONT}`;
    const rowH = 18 * ui, padX = 10 * ui, icon = 16 * ui, gap = 14 * ui;
    let x = padX, row = 0;
    const items = [];
    for (const it of this._legendItems()) {
      const w = icon + 4 * ui + ctx.measureText(it[2]).width;
      if (x + w > cssW - padX && x > padX) { row++; x = padX; }
      items.push({ it, x, row });
      x += w + gap;
    }
    ctx.restore();
    this.legendItems = items;
    this.legendRowH = rowH;
    this.legendH = Math.round((row + 1) * rowH + 8 * ui);
  }

  _drawLegend(ctx) {
    const ui = this.ui, d = this.dpr;
    const top = this.cssH - this.legendH;
    ctx.setTransform(d, 0, 0, d, 0, 0);
    ctx.fillStyle = "#ffffff";
    ctx.fillRect(0, top, this.cssW, this.legendH);
    ctx.strokeStyle = "#c9c9c2"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(0, top + 0.5); ctx.lineTo(this.cssW, top + 0.5); ctx.stroke();
    ctx.font = `${12 * ui}px ${FONT}`;
    ctx.textBaseline = "middle"; ctx.textAlign = "left";
    for (const { it, x, row } of this.legendItems) {
      const cy = top + 4 * ui + row * this.legendRowH + this.legendRowH / 2;
      const cx = x + 8 * ui;
      const [kind, colour, label] = it;
      ctx.lineWidth = 1.5 * ui;
      if (kind === "robot") {
        ctx.fillStyle = colour; ctx.strokeStyle = COLOURS.wall;
        ctx.beginPath(); ctx.arc(cx, cy, 6 * ui, 0, TAU); ctx.fill(); ctx.stroke();
      } else if (kind === "square") {
        ctx.fillStyle = colour; ctx.strokeStyle = COLOURS.wall;
        ctx.beginPath(); ctx.rect(cx - 6 * ui, cy - 6 * ui, 12 * ui, 12 * ui); ctx.fill(); ctx.stroke();
      } else if (kind === "delay") {
        ctx.fillStyle = COLOURS.blue;
        ctx.fillRect(cx - 7 * ui, cy - 7 * ui, 14 * ui, 14 * ui);
        this._delayMarks(ctx, [cx], [cy], [0], 1, 14 * ui, 3 * ui);
      } else if (kind === "cell") {
        ctx.fillStyle = colour; ctx.fillRect(cx - 6 * ui, cy - 6 * ui, 12 * ui, 12 * ui);
      } else if (kind === "departure") {
        this._departureIcon(ctx, cx, cy, 6.5 * ui, 1.5 * ui);
      } else if (kind === "unloading") {
        this._unloadingIcon(ctx, cx, cy, 6.5 * ui, 1.5 * ui);
      } else if (kind === "charger") {
        this._chargerIcon(ctx, cx, cy, 14 * ui, 10 * ui, 1 * ui);
      } else if (kind === "person") {
        this._personIcon(ctx, cx, cy, 7 * ui, 1.2 * ui);
      } else if (kind === "zones") {
        ctx.lineWidth = 1.5 * ui;
        ctx.setLineDash([3 * ui, 2 * ui]);
        ctx.strokeStyle = COLOURS.zoneWarning;
        ctx.beginPath(); ctx.arc(cx, cy, 7 * ui, 0, TAU); ctx.stroke();
        ctx.strokeStyle = COLOURS.zoneProtective;
        ctx.beginPath(); ctx.arc(cx, cy, 4 * ui, 0, TAU); ctx.stroke();
        ctx.setLineDash([]);
      } else if (kind === "queue") {
        this._badge(ctx, cx - 7 * ui, cy - 7.5 * ui, "3", ui);
      } else if (kind === "bottleneck") {
        ctx.strokeStyle = colour; ctx.lineWidth = 2.5 * ui;
        ctx.beginPath(); ctx.arc(cx, cy, 6 * ui, 0, TAU); ctx.stroke();
      } else if (kind === "battery") {
        const w = 5 * ui;
        [COLOURS.batteryOk, COLOURS.batteryLow, COLOURS.batteryCritical].forEach((c, k) => {
          ctx.fillStyle = c; ctx.fillRect(cx - 8 * ui + k * (w + 0.5 * ui), cy - 2.5 * ui, w, 5 * ui);
        });
      }
      ctx.fillStyle = "#1d2228";
      ctx.fillText(label, x + 16 * ui + 4 * ui, cy);
    }
  }

  /** A person from above, as on the floor: shoulders (an ellipse) and head. */
  _personIcon(ctx, x, y, r, lw) {
    ctx.lineWidth = lw;
    ctx.fillStyle = COLOURS.person; ctx.strokeStyle = COLOURS.personEdge;
    ctx.beginPath(); ctx.ellipse(x, y, r, r * 0.62, 0, 0, TAU); ctx.fill(); ctx.stroke();
    ctx.fillStyle = COLOURS.personHead;
    ctx.beginPath(); ctx.arc(x, y, r * 0.42, 0, TAU); ctx.fill(); ctx.stroke();
  }

  _departureIcon(ctx, x, y, r, lw) {
    ctx.strokeStyle = COLOURS.departure; ctx.lineWidth = lw;
    ctx.beginPath(); ctx.arc(x, y, r, 0, TAU); ctx.stroke();
    const k = r * Math.SQRT1_2;
    ctx.beginPath();
    ctx.moveTo(x - k, y - k); ctx.lineTo(x + k, y + k);
    ctx.moveTo(x + k, y - k); ctx.lineTo(x - k, y + k);
    ctx.stroke();
  }

  _unloadingIcon(ctx, x, y, r, lw) {
    ctx.strokeStyle = COLOURS.unloading; ctx.lineWidth = lw;
    ctx.beginPath(); ctx.arc(x, y, r, 0, TAU); ctx.stroke();
    ctx.beginPath(); ctx.arc(x, y, r * 0.6, 0, TAU); ctx.stroke();
  }

  _chargerIcon(ctx, x, y, w, h, lw) {
    ctx.fillStyle = COLOURS.charger; ctx.strokeStyle = COLOURS.chargerEdge; ctx.lineWidth = lw;
    ctx.beginPath(); ctx.rect(x - w / 2, y - h / 2, w, h); ctx.fill(); ctx.stroke();
    // a lightning bolt
    ctx.fillStyle = COLOURS.chargerEdge;
    ctx.beginPath();
    ctx.moveTo(x + w * 0.08, y - h * 0.38);
    ctx.lineTo(x - w * 0.16, y + h * 0.06);
    ctx.lineTo(x - w * 0.01, y + h * 0.06);
    ctx.lineTo(x - w * 0.08, y + h * 0.38);
    ctx.lineTo(x + w * 0.16, y - h * 0.06);
    ctx.lineTo(x + w * 0.01, y - h * 0.06);
    ctx.closePath(); ctx.fill();
  }

  /** The world rectangle in view, grown by ``margin`` world px. */
  _visibleWorld(margin) {
    const [x0, y0] = this.toWorld(0, this.areaTop);
    const [x1, y1] = this.toWorld(this.cssW, this.areaTop + this.areaH);
    return [x0 - margin, y0 - margin, x1 + margin, y1 + margin];
  }

  _cellInView(c, v) { return c.x + c.w >= v[0] && c.x <= v[2] && c.y + c.h >= v[1] && c.y <= v[3]; }

  _drawBackground(cells) {
    const ctx = this.bg.getContext("2d", { alpha: false });
    const L = this.layout, s = this.scale, d = this.dpr;
    const view = this._visibleWorld(this.aisle);
    const inView = (x, y) => x >= view[0] && x <= view[2] && y >= view[1] && y <= view[3];
    const segInView = (ax, ay, bx, by) => Math.max(ax, bx) >= view[0] && Math.min(ax, bx) <= view[2]
      && Math.max(ay, by) >= view[1] && Math.min(ay, by) <= view[3];
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = COLOURS.backdrop;
    ctx.fillRect(0, 0, this.bg.width, this.bg.height);
    ctx.save();
    ctx.beginPath();
    ctx.rect(0, this.areaTop * d, this.bg.width, this.areaH * d);
    ctx.clip();
    this._worldTransform(ctx);
    const px = 1 / s;  // one css pixel in world units
    const b = L.bounds;
    ctx.fillStyle = COLOURS.floor;
    ctx.fillRect(b[0], b[1], b[2] - b[0], b[3] - b[1]);
    if (this.grid) this._drawGrid(ctx, view);

    const nodes = L.nodes;
    // spurs (two-way, dashed)
    ctx.strokeStyle = COLOURS.highway;
    ctx.lineWidth = 1.5 * px;
    ctx.setLineDash([4 * px, 3 * px]);
    ctx.beginPath();
    for (const [c, u] of L.spurs || []) {
      if (!segInView(nodes[c].x, nodes[c].y, nodes[u].x, nodes[u].y)) continue;
      ctx.moveTo(nodes[c].x, nodes[c].y); ctx.lineTo(nodes[u].x, nodes[u].y);
    }
    ctx.stroke();
    ctx.setLineDash([]);
    // highway edges with arrows
    ctx.beginPath();
    const edges = L.edges.filter(([u, v]) => segInView(nodes[u].x, nodes[u].y, nodes[v].x, nodes[v].y));
    for (const [u, v] of edges) { ctx.moveTo(nodes[u].x, nodes[u].y); ctx.lineTo(nodes[v].x, nodes[v].y); }
    ctx.stroke();
    const arrow = Math.min(this.aisle * 0.16, 9 * px * Math.max(1, this.ui));
    if (arrow * s >= 2.5) {
      ctx.fillStyle = COLOURS.highway;
      ctx.beginPath();
      const spacing = Math.max(this.cell * 2, 60 * px);
      for (const [u, v] of edges) {
        const ax = nodes[u].x, ay = nodes[u].y, bx = nodes[v].x, by = nodes[v].y;
        const len = Math.hypot(bx - ax, by - ay);
        if (len <= 0) continue;
        const ux = (bx - ax) / len, uy = (by - ay) / len;
        const count = Math.max(1, Math.round(len / spacing));
        for (let j = 0; j < count; j++) {
          const t = (j + 0.5) / count;
          const cx = ax + (bx - ax) * t + ux * arrow * 0.5, cy = ay + (by - ay) * t + uy * arrow * 0.5;
          ctx.moveTo(cx, cy);
          ctx.lineTo(cx - ux * arrow * 1.6 - uy * arrow * 0.8, cy - uy * arrow * 1.6 + ux * arrow * 0.8);
          ctx.lineTo(cx - ux * arrow * 1.6 + uy * arrow * 0.8, cy - uy * arrow * 1.6 - ux * arrow * 0.8);
          ctx.closePath();
        }
      }
      ctx.fill();
    }

    // warehouse outline
    ctx.strokeStyle = COLOURS.wall;
    ctx.lineWidth = 2.5 * px * Math.max(1, this.ui * 0.8);
    ctx.strokeRect(b[0], b[1], b[2] - b[0], b[3] - b[1]);

    // zones
    const zr = this.aisle * 0.3;
    const seen = (k) => inView(nodes[k].x, nodes[k].y);
    for (const k of (L.departure || []).filter(seen)) this._departureIcon(ctx, nodes[k].x, nodes[k].y, zr, 2 * px);
    for (const k of (L.unloading || []).filter(seen)) this._unloadingIcon(ctx, nodes[k].x, nodes[k].y, zr, 2 * px);
    for (const k of (L.chargers || []).filter(seen)) {
      this._chargerIcon(ctx, nodes[k].x, nodes[k].y, this.aisle * 0.5, this.aisle * 0.3, 1.2 * px);
    }
    // labels: highway letters in the crossing's top-left corner, charger names beside them
    const label = this.aisle * 0.24;
    if (label * s >= 7) {
      ctx.font = `bold ${label}px ${FONT}`;
      ctx.fillStyle = "#3a4048";
      ctx.textAlign = "left"; ctx.textBaseline = "top";
      const off = this.aisle * 0.44;
      for (const nd of nodes) if (nd.kind !== "charger" && inView(nd.x, nd.y)) ctx.fillText(nd.name, nd.x - off, nd.y - off);
      ctx.font = `${label * 0.85}px ${FONT}`;
      ctx.textBaseline = "middle";
      for (const k of (L.chargers || []).filter(seen)) {
        const nd = nodes[k];
        ctx.fillText(nd.name, nd.x + this.aisle * 0.3, nd.y);
      }
    }
    // delivered goods label (a grid replay counts finished tasks in the banner only)
    ctx.font = `${this.goodsLabel}px ${FONT}`;
    ctx.fillStyle = "#3a4048"; ctx.textAlign = "left"; ctx.textBaseline = "top";
    if (!this.grid) ctx.fillText("delivered", this.goodsX0, this.goodsTop - this.goodsLabel * 0.1);
    ctx.restore();
    this._drawLegend(ctx);
    // the cells, on their own layer
    const cl = this.cellLayer.getContext("2d");
    cl.setTransform(1, 0, 0, 1, 0, 0);
    cl.clearRect(0, 0, this.cellLayer.width, this.cellLayer.height);
    cl.save();
    cl.beginPath();
    cl.rect(0, this.areaTop * d, this.cellLayer.width, this.areaH * d);
    cl.clip();
    this._worldTransform(cl);
    this._drawCells(cl, cells, L.cells.filter((c) => this._cellInView(c, view)));
    cl.restore();
    this.bgValid = true;
  }

  /** A grid's obstacles (world transform set; a cell is `cell_size` px), a run of `@` per
   * rectangle, only the rows in view; thin cell lines once a cell is 12 px or more. */
  _drawGrid(ctx, view) {
    const G = this.grid, px = 1 / this.scale, k = this.cell;
    const r0 = Math.max(0, Math.floor(view[1] / k)), r1 = Math.min(G.rows, Math.ceil(view[3] / k));
    const c0 = Math.max(0, Math.floor(view[0] / k)), c1 = Math.min(G.cols, Math.ceil(view[2] / k));
    ctx.fillStyle = COLOURS.wall;
    ctx.beginPath();
    for (let r = r0; r < r1; r++) {
      const row = G.cells[r];
      let c = c0;
      while (c < c1) {
        if (row[c] !== "@") { c++; continue; }
        let e = c;
        while (e < c1 && row[e] === "@") e++;
        ctx.rect(c * k, r * k, (e - c) * k, k);
        c = e;
      }
    }
    ctx.fill();
    if (this.scale * k < 12) return;
    ctx.strokeStyle = "#d8dadc";
    ctx.lineWidth = px;
    ctx.beginPath();
    for (let r = r0; r <= r1; r++) { ctx.moveTo(c0 * k, r * k); ctx.lineTo(c1 * k, r * k); }
    for (let c = c0; c <= c1; c++) { ctx.moveTo(c * k, r0 * k); ctx.lineTo(c * k, r1 * k); }
    ctx.stroke();
  }

  /** Each robot's goal in a grid replay: a small square on the goal cell in the robot's
   * colour, and a line to it from the selected robot. */
  _drawGoals(ctx, frame, info) {
    const goals = info.goals, cols = this.grid.cols, px = 1 / this.scale, k = this.cell, q = 0.3 * k;
    const mask = CODEC.stateMask;
    for (let g = 0; g < GROUP_COLOURS.length; g++) {
      let any = false;
      ctx.beginPath();
      for (let i = 0; i < goals.length; i++) {
        const c = goals[i];
        if (c < 0 || STATE_GROUP[frame.state[i] & mask] !== g) continue;
        ctx.rect(((c % cols) + 0.5) * k - q, (Math.floor(c / cols) + 0.5) * k - q, 2 * q, 2 * q);
        any = true;
      }
      if (!any) continue;
      ctx.fillStyle = GROUP_COLOURS[g];
      ctx.fill();
      ctx.lineWidth = Math.min(px, 0.06 * k);
      ctx.strokeStyle = COLOURS.wall;
      ctx.stroke();
    }
    const sel = info.selected;
    if (sel >= 0 && sel < goals.length && goals[sel] >= 0) {
      const c = goals[sel];
      ctx.strokeStyle = COLOURS.select;
      ctx.lineWidth = Math.max(2 * px, 0.08 * k);
      ctx.beginPath();
      ctx.moveTo(frame.x[sel], frame.y[sel]);
      ctx.lineTo(((c % cols) + 0.5) * k, (Math.floor(c / cols) + 0.5) * k);
      ctx.stroke();
    }
  }

  /** Paint storage cells (world transform set): fill, white borders, ids when legible. */
  _drawCells(ctx, cells, list) {
    const s = this.scale, px = 1 / s;
    const full = new Path2D(), empty = new Path2D(), edges = new Path2D();
    for (const c of list) {
      (cells && cells[c.id] ? full : empty).rect(c.x, c.y, c.w, c.h);
      edges.rect(c.x, c.y, c.w, c.h);
    }
    ctx.fillStyle = COLOURS.cellFull; ctx.fill(full);
    ctx.fillStyle = COLOURS.cellEmpty; ctx.fill(empty);
    ctx.strokeStyle = COLOURS.floor;
    ctx.lineWidth = Math.min(1.5 * px, this.cell * 0.04);
    ctx.stroke(edges);
    if (this.cell * s >= 16) {
      ctx.fillStyle = "#ffffff";
      ctx.textAlign = "center"; ctx.textBaseline = "middle";
      ctx.font = `bold ${this.cell * 0.3}px ${FONT}`;
      for (const c of list) ctx.fillText(String(c.id), c.x + c.w / 2, c.y + c.h / 2);
    }
  }

  /** Repaint only the cells whose goods changed. Each changed cell's box (snapped out to
   *  whole device pixels) is cleared and every cell touching it redrawn inside it, so the
   *  pixels are exactly those of a fresh drawing. */
  _updateCells(cells) {
    const old = this.cellsDrawn, L = this.layout;
    const changed = [];
    for (let k = 0; k < cells.length; k++) {
      if (cells[k] !== old[k]) {
        changed.push(L.cells[k]);
        if (changed.length > 400) return false;  // many: redraw everything instead
      }
    }
    const view = this._visibleWorld(this.aisle);
    const list = changed.filter((c) => this._cellInView(c, view));
    if (list.length) {
      const ctx = this.cellLayer.getContext("2d");
      const d = this.dpr, s = this.scale, ox = this.ox, oy = this.oy;
      const pad = 2 / (d * s);  // two device pixels, in world px
      for (const c of list) {
        // the box in device pixels, snapped outwards
        const bx0 = Math.floor(d * (ox + (c.x - pad) * s)), by0 = Math.floor(d * (oy + (c.y - pad) * s));
        const bx1 = Math.ceil(d * (ox + (c.x + c.w + pad) * s)), by1 = Math.ceil(d * (oy + (c.y + c.h + pad) * s));
        const top = Math.round(this.areaTop * d), bottom = Math.round((this.areaTop + this.areaH) * d);
        const cy0 = Math.max(by0, top), cy1 = Math.min(by1, bottom);
        if (cy1 <= cy0) continue;
        // back to world px, to find the cells that touch the box
        const wx0 = (bx0 / d - ox) / s, wx1 = (bx1 / d - ox) / s, wy0 = (by0 / d - oy) / s, wy1 = (by1 / d - oy) / s;
        ctx.save();
        ctx.setTransform(1, 0, 0, 1, 0, 0);
        ctx.beginPath();
        ctx.rect(bx0, cy0, bx1 - bx0, cy1 - cy0);
        ctx.clip();
        ctx.clearRect(bx0, cy0, bx1 - bx0, cy1 - cy0);
        this._worldTransform(ctx);
        this._drawCells(ctx, cells, this._cellsNear(wx0, wy0, wx1, wy1));
        ctx.restore();
      }
    }
    this.cellsDrawn.set(cells);
    return true;
  }

  // --------------------------------------------------------------- frame
  /**
   * Draw one frame.
   * frame: {x, y (Float32Array N), heading (Uint8Array), state (Uint8Array, bit 7 = marked),
   *         energy (Uint16Array), step, S, C, delivered}
   * info:  {cells (Uint8Array), last (frame index or null), T, done, outcome, goodsTotal,
   *         selected (-1 or id), route ([[x, y], ...]), blinkOn, next, alpha, mode}
   */
  draw(frame, info) {
    const ctx = this.ctx, d = this.dpr;
    const cells = info.cells;
    if (!this.bgValid || !cells || !this.cellsDrawn || cells.length !== this.cellsDrawn.length
        || (!sameCells(cells, this.cellsDrawn) && !this._updateCells(cells))) {
      this.cellsDrawn = cells ? Uint8Array.from(cells) : null;
      this._drawBackground(cells);
    }
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(this.bg, 0, 0);
    ctx.drawImage(this.cellLayer, 0, 0);
    this._drawBanner(ctx, frame, info);
    if (!frame) return;
    ctx.save();
    ctx.beginPath();
    ctx.rect(0, this.areaTop * d, this.canvas.width, this.areaH * d);
    ctx.clip();
    this._worldTransform(ctx);
    if (this.grid) {
      if (info.goals) this._drawGoals(ctx, frame, info);
    } else {
      this._drawDelivered(ctx, frame.delivered);
    }
    if (info.selected >= 0 && info.route && info.route.length > 1) this._drawRoute(ctx, frame, info);
    this._drawRobots(ctx, frame, info);
    if (this.humans && frame.hx && frame.hx.length) this._drawPeople(ctx, frame, info);
    this.badges = [];
    if (info.queues && !this.grid) this._drawQueues(ctx, info.queues);
    ctx.restore();
  }

  /** A badge of the robots queued, with its top-left corner at css point (x, y). */
  _badge(ctx, x, y, label, ui) {
    ctx.save();
    ctx.font = `bold ${11 * ui}px ${FONT}`;
    const w = Math.max(15 * ui, ctx.measureText(label).width + 8 * ui), h = 15 * ui;
    ctx.fillStyle = COLOURS.queue;
    ctx.beginPath();
    if (ctx.roundRect) ctx.roundRect(x, y, w, h, 4 * ui); else ctx.rect(x, y, w, h);
    ctx.fill();
    ctx.fillStyle = COLOURS.queueText;
    ctx.textAlign = "center"; ctx.textBaseline = "middle";
    ctx.fillText(label, x + w / 2, y + h / 2 + 0.5 * ui);
    ctx.restore();
    return [w, h];
  }

  /** The resources' queues (docs/viewer.md): a ring around the bottleneck (every charger when
   * it is the chargers' queue), and at each resource with robots queued a badge with their
   * number, beside its node (a lane's: along the lane). queues: {resources, counts, bottleneck}; the charger queue has
   * no node of its own and is listed beside the map only. */
  _drawQueues(ctx, queues) {
    const ui = this.ui, d = this.dpr, nodes = this.layout.nodes;
    const b = queues.bottleneck;
    ctx.setTransform(d, 0, 0, d, 0, 0);
    if (b) {
      const ring = b.kind === "charger-queue" ? (this.layout.chargers || []) : [this.nodeOf.get(b.node)];
      ctx.strokeStyle = COLOURS.bottleneck; ctx.lineWidth = 3 * ui;
      ctx.beginPath();
      for (const k of ring) {
        if (k === undefined) continue;
        const [sx, sy] = this.toScreen(nodes[k].x, nodes[k].y);
        const r = Math.max(9 * ui, this.aisle * 0.5 * this.scale);
        ctx.moveTo(sx + r, sy); ctx.arc(sx, sy, r, 0, TAU);
      }
      ctx.stroke();
    }
    const off = Math.max(6 * ui, this.aisle * 0.3 * this.scale);
    // A node's badge sits beside it; a lane's ("U->V") two thirds of the way to V, where its
    // queue stands, so that the lanes U->V and V->U of a two-way aisle do not share a spot.
    const at = (u) => {
      const ends = u.kind === "lane" ? u.node.split("->") : [u.node];
      const ks = ends.map((name) => this.nodeOf.get(name));
      if (ks.some((k) => k === undefined)) return null;
      const w = ks.length === 2 ? [1 / 3, 2 / 3] : [1];
      const x = ks.reduce((a, k, j) => a + w[j] * nodes[k].x, 0);
      const y = ks.reduce((a, k, j) => a + w[j] * nodes[k].y, 0);
      return this.toScreen(x, y);
    };
    queues.resources.forEach((u, j) => {
      const count = queues.counts[j];
      const p = u.kind === "charger-queue" ? null : at(u);
      if (!count || !p) return;
      const [sx, sy] = p;
      const x = sx + off, y = sy - off - 15 * ui;
      const [w, h] = this._badge(ctx, x, y, String(count), ui);
      this.badges.push({ node: u.node, kind: u.kind, count, x, y, w, h });
    });
  }

  /** People as seen from above (shoulders and head), and on demand (info.zones) the
   * protective and warning zones of the robots near them. */
  _drawPeople(ctx, frame, info) {
    const HX = frame.hx, HY = frame.hy, r = this.humans.radius, px = 1 / this.scale;
    const zones = this.humans.zones;
    if (info.zones && zones) {
      const [prot, warn] = zones, xs = this.lastXs || frame.x, ys = this.lastYs || frame.y;
      ctx.lineWidth = 1.2 * px;
      ctx.setLineDash([5 * px, 4 * px]);
      for (let i = 0; i < this.n; i++) {
        let near = false;
        for (let k = 0; k < HX.length && !near; k++) {
          const dx = HX[k] - xs[i], dy = HY[k] - ys[i];
          near = dx * dx + dy * dy < warn * warn * 1.5;
        }
        if (!near) continue;
        ctx.strokeStyle = "rgba(230, 160, 0, 0.9)";
        ctx.beginPath(); ctx.arc(xs[i], ys[i], warn, 0, TAU); ctx.stroke();
        ctx.strokeStyle = "rgba(200, 30, 30, 0.9)";
        ctx.beginPath(); ctx.arc(xs[i], ys[i], prot, 0, TAU); ctx.stroke();
      }
      ctx.setLineDash([]);
    }
    ctx.fillStyle = COLOURS.person;
    ctx.strokeStyle = COLOURS.personEdge;
    ctx.lineWidth = Math.min(1.2 * px, r * 0.15);
    ctx.beginPath();
    for (let k = 0; k < HX.length; k++) {
      ctx.moveTo(HX[k] + r, HY[k]);
      ctx.ellipse(HX[k], HY[k], r, r * 0.62, 0, 0, TAU);
    }
    ctx.fill(); ctx.stroke();
    ctx.fillStyle = COLOURS.personHead;
    ctx.beginPath();
    for (let k = 0; k < HX.length; k++) {
      ctx.moveTo(HX[k] + r * 0.42, HY[k]);
      ctx.arc(HX[k], HY[k], r * 0.42, 0, TAU);
    }
    ctx.fill(); ctx.stroke();
  }

  _drawDelivered(ctx, delivered) {
    const q = this.goodsSize, pitch = q + this.goodsGap;
    const cap = this.goodsPerRow * this.goodsRows;
    const shown = delivered > cap ? cap - 1 : delivered;
    const x0 = this.goodsX0 + this.cell * 1.6;
    ctx.fillStyle = COLOURS.cellFull;
    ctx.beginPath();
    for (let k = 0; k < shown; k++) {
      const row = Math.floor(k / this.goodsPerRow), col = k % this.goodsPerRow;
      ctx.rect(x0 + col * pitch, this.goodsTop + row * pitch, q, q);
    }
    ctx.fill();
    if (delivered > cap) {
      ctx.fillStyle = "#3a4048";
      ctx.font = `bold ${q * 1.1}px ${FONT}`;
      ctx.textAlign = "left"; ctx.textBaseline = "top";
      const k = cap - 1, row = Math.floor(k / this.goodsPerRow), col = k % this.goodsPerRow;
      ctx.fillText(`+${delivered - shown}`, x0 + col * pitch, this.goodsTop + row * pitch - q * 0.05);
    }
  }

  _drawRoute(ctx, frame, info) {
    const px = 1 / this.scale, i = info.selected, r = info.route;
    ctx.strokeStyle = stateColour(frame.state[i]);
    ctx.lineWidth = Math.max(2.5 * px, this.radius[i] * 0.22);
    ctx.lineJoin = "round";
    ctx.setLineDash([8 * px, 5 * px]);
    ctx.beginPath();
    ctx.moveTo(r[0][0], r[0][1]);
    for (let k = 1; k < r.length; k++) ctx.lineTo(r[k][0], r[k][1]);
    ctx.stroke();
    ctx.setLineDash([]);
    const e = r[r.length - 1];
    ctx.beginPath();
    ctx.arc(e[0], e[1], Math.max(4 * px, this.radius[i] * 0.35), 0, TAU);
    ctx.fillStyle = ctx.strokeStyle; ctx.fill();
  }

  _drawRobots(ctx, frame, info) {
    const n = this.n, s = this.scale, px = 1 / s;
    const X = frame.x, Y = frame.y, H = frame.heading, ST = frame.state, E = frame.energy;
    const mask = CODEC.stateMask, turn = TAU / CODEC.headingSteps;  // the codec's, read once per frame
    const next = info.next, alpha = info.alpha || 0;
    // positions (interpolated between two frames when playing slowly)
    let xs = X, ys = Y;
    if (next && alpha > 0) {
      xs = this._ix || (this._ix = new Float32Array(n));
      ys = this._iy || (this._iy = new Float32Array(n));
      for (let i = 0; i < n; i++) {
        const dx = next.x[i] - X[i], dy = next.y[i] - Y[i];
        if (dx * dx + dy * dy < 400) { xs[i] = X[i] + dx * alpha; ys[i] = Y[i] + dy * alpha; }
        else { xs[i] = X[i]; ys[i] = Y[i]; }
      }
    }
    this.lastXs = xs; this.lastYs = ys;
    if (this.side) { this._drawSquares(ctx, frame, info, xs, ys); return; }
    const small = this.maxRadius * s < 4;  // a few pixels: a plain dot says enough
    // only the robots in view (zoomed in on a large fleet, most are not)
    const m = this.maxRadius * 3;
    const [vx0, vy0] = this.toWorld(0, this.areaTop), [vx1, vy1] = this.toWorld(this.cssW, this.areaTop + this.areaH);
    const vis = this._vis && this._vis.length === n ? this._vis : (this._vis = new Int32Array(n));
    let nv = 0;
    for (let i = 0; i < n; i++) {
      if (xs[i] >= vx0 - m && xs[i] <= vx1 + m && ys[i] >= vy0 - m && ys[i] <= vy1 + m) vis[nv++] = i;
    }
    // bodies, one path per colour
    ctx.lineWidth = Math.min(1.2 * px, this.maxRadius * 0.12);
    ctx.strokeStyle = COLOURS.wall;
    for (let g = 0; g < GROUP_COLOURS.length; g++) {
      let any = false;
      ctx.beginPath();
      for (let j = 0; j < nv; j++) {
        const i = vis[j];
        if (STATE_GROUP[ST[i] & mask] !== g) continue;
        const r = this.radius[i];
        ctx.moveTo(xs[i] + r, ys[i]);
        ctx.arc(xs[i], ys[i], r, 0, TAU);
        any = true;
      }
      if (!any) continue;
      ctx.fillStyle = GROUP_COLOURS[g];
      ctx.fill();
      if (!small) ctx.stroke();
    }
    // selection ring
    const sel = info.selected;
    if (sel >= 0 && sel < n) {
      ctx.beginPath();
      ctx.arc(xs[sel], ys[sel], this.radius[sel] + 3 * px, 0, TAU);
      ctx.lineWidth = 3 * px; ctx.strokeStyle = COLOURS.select; ctx.stroke();
    }
    if (small) return;
    // heading lines
    ctx.beginPath();
    for (let j = 0; j < nv; j++) {
      const i = vis[j];
      const a = H[i] * turn, r = this.radius[i];
      ctx.moveTo(xs[i], ys[i]);
      ctx.lineTo(xs[i] + Math.cos(a) * r, ys[i] + Math.sin(a) * r);
    }
    ctx.lineWidth = Math.max(1.2 * px, this.maxRadius * 0.16);
    ctx.strokeStyle = COLOURS.wall;
    ctx.lineCap = "round";
    ctx.stroke();
    ctx.lineCap = "butt";
    // battery bars above each robot (none on a grid: the competition has no batteries)
    if (this.maxRadius * s < 4 || this.grid) return;
    const back = new Path2D(), levels = [new Path2D(), new Path2D(), new Path2D()];
    const blinkOn = info.blinkOn !== false;
    for (let j = 0; j < nv; j++) {
      const i = vis[j];
      const r = this.radius[i];
      const w = 2 * r, h = Math.max(r * 0.3, 2.5 * px);
      const bx = xs[i] - r, by = ys[i] - r - r * 0.22 - h;
      back.rect(bx - 0.5 * px, by - 0.5 * px, w + px, h + px);
      if ((ST[i] & CODEC.marked) && !blinkOn) continue;
      const f = energyFraction(E[i]);
      const lvl = f < this.thrFrac - 1e-9 ? 2 : (f < this.lowFrac ? 1 : 0);
      if (f > 0) levels[lvl].rect(bx, by, w * Math.min(1, f), h);
    }
    ctx.fillStyle = COLOURS.batteryBack; ctx.fill(back);
    ctx.fillStyle = COLOURS.batteryOk; ctx.fill(levels[0]);
    ctx.fillStyle = COLOURS.batteryLow; ctx.fill(levels[1]);
    ctx.fillStyle = COLOURS.batteryCritical; ctx.fill(levels[2]);
  }

  /** The robots of a 2026 replay (docs/lorr.md): each one its square of side agentSize
   * cells, centred where the frame puts it (its cell's top-left corner plus half the side,
   * slid along its heading while a move is under way), in its state's colour with its
   * heading; a robot held by a delay (the marked bit) outlined in the delay colour with a
   * pause mark. */
  _drawSquares(ctx, frame, info, xs, ys) {
    const n = this.n, s = this.scale, px = 1 / s, side = this.side, half = side / 2;
    const H = frame.heading, ST = frame.state;
    const mask = CODEC.stateMask, turn = TAU / CODEC.headingSteps;
    const small = half * s < 4;  // a few pixels: the square alone
    const [vx0, vy0] = this.toWorld(0, this.areaTop), [vx1, vy1] = this.toWorld(this.cssW, this.areaTop + this.areaH);
    const vis = this._vis && this._vis.length === n ? this._vis : (this._vis = new Int32Array(n));
    let nv = 0;
    for (let i = 0; i < n; i++) {
      if (xs[i] >= vx0 - side && xs[i] <= vx1 + side && ys[i] >= vy0 - side && ys[i] <= vy1 + side) vis[nv++] = i;
    }
    ctx.lineWidth = Math.min(1.2 * px, side * 0.06);
    ctx.strokeStyle = COLOURS.wall;
    for (let g = 0; g < GROUP_COLOURS.length; g++) {
      let any = false;
      ctx.beginPath();
      for (let j = 0; j < nv; j++) {
        const i = vis[j];
        if (STATE_GROUP[ST[i] & mask] !== g) continue;
        ctx.rect(xs[i] - half, ys[i] - half, side, side);
        any = true;
      }
      if (!any) continue;
      ctx.fillStyle = GROUP_COLOURS[g];
      ctx.fill();
      if (!small) ctx.stroke();
    }
    const sel = info.selected;
    if (sel >= 0 && sel < n) {
      ctx.lineWidth = 3 * px; ctx.strokeStyle = COLOURS.select;
      ctx.strokeRect(xs[sel] - half - 2.5 * px, ys[sel] - half - 2.5 * px, side + 5 * px, side + 5 * px);
    }
    if (!small) {
      ctx.beginPath();
      for (let j = 0; j < nv; j++) {
        const i = vis[j], a = H[i] * turn;
        ctx.moveTo(xs[i], ys[i]);
        ctx.lineTo(xs[i] + Math.cos(a) * half * 0.8, ys[i] + Math.sin(a) * half * 0.8);
      }
      ctx.lineWidth = Math.max(1.2 * px, side * 0.08);
      ctx.strokeStyle = COLOURS.wall;
      ctx.lineCap = "round";
      ctx.stroke();
      ctx.lineCap = "butt";
    }
    // held by a delay: on top of the body and its heading
    let k = 0;
    const held = this._held && this._held.length === n ? this._held : (this._held = new Int32Array(n));
    for (let j = 0; j < nv; j++) if (ST[vis[j]] & CODEC.marked) held[k++] = vis[j];
    if (k) this._delayMarks(ctx, xs, ys, held, k, side, Math.min(side * 0.25, Math.max(2 * px, side * 0.12)),
      side * s >= 10);
  }

  /** The delay marks of `count` robots (indices in idx) of side `side`, centred at (xs, ys):
   * an outline of width lw inside the square and, if `mark`, a pause sign at its centre (a
   * disc in the delay colour with two white bars). */
  _delayMarks(ctx, xs, ys, idx, count, side, lw, mark = true) {
    const half = side / 2;
    ctx.strokeStyle = COLOURS.delay; ctx.lineWidth = lw;
    ctx.beginPath();
    for (let j = 0; j < count; j++) {
      const i = idx[j];
      ctx.rect(xs[i] - half + lw / 2, ys[i] - half + lw / 2, side - lw, side - lw);
    }
    ctx.stroke();
    if (!mark) return;
    const r = side * 0.24, bw = side * 0.06, bh = side * 0.24, gap = side * 0.05;
    ctx.fillStyle = COLOURS.delay;
    ctx.beginPath();
    for (let j = 0; j < count; j++) {
      const i = idx[j];
      ctx.moveTo(xs[i] + r, ys[i]);
      ctx.arc(xs[i], ys[i], r, 0, TAU);
    }
    ctx.fill();
    ctx.fillStyle = COLOURS.delayMark;
    ctx.beginPath();
    for (let j = 0; j < count; j++) {
      const i = idx[j];
      ctx.rect(xs[i] - gap - bw, ys[i] - bh / 2, bw, bh);
      ctx.rect(xs[i] + gap, ys[i] - bh / 2, bw, bh);
    }
    ctx.fill();
  }

  _drawBanner(ctx, frame, info) {
    const ui = this.ui, d = this.dpr, h = this.bannerH;
    ctx.setTransform(d, 0, 0, d, 0, 0);
    ctx.fillStyle = COLOURS.banner;
    ctx.fillRect(0, 0, this.cssW, h);
    ctx.fillStyle = COLOURS.bannerText;
    ctx.textBaseline = "middle"; ctx.textAlign = "left";
    ctx.font = `bold ${13 * ui}px ${FONT}`;
    let x = 10 * ui;
    const y = h / 2;
    const title = this.title || "MultiBots";
    ctx.fillText(title, x, y);
    x += ctx.measureText(title).width + 18 * ui;
    if (!frame) return;
    const parts = bannerParts(frame, { ...info, grid: !!this.grid, delays: this.y2026 });
    for (const [k, v] of parts) {
      ctx.font = `${12 * ui}px ${FONT}`;
      ctx.fillStyle = "#b9c0c8";
      ctx.fillText(k, x, y);
      x += ctx.measureText(k).width + 5 * ui;
      ctx.font = `bold ${13 * ui}px ${FONT}`;
      ctx.fillStyle = COLOURS.bannerText;
      ctx.fillText(v, x, y);
      x += ctx.measureText(v).width + 16 * ui;
    }
  }
}

export function formatT(info) {
  if (!info.done) return "\u2014";
  return info.T === null || info.T === undefined ? "incomplete" : String(info.T);
}

export function bannerParts(frame, info) {
  const step = info.last !== null && info.last !== undefined ? `${frame.step} / ${info.last}` : String(frame.step);
  // A grid replay: S counts refused joint actions, delivered the tasks finished (docs/lorr.md).
  // A 2026 replay's C counts the delays drawn so far.
  if (info.grid) {
    return [["step", step], ["errors", String(frame.S)], ["finished", String(frame.delivered)],
      ...(info.delays ? [["delays", String(frame.C)]] : [])];
  }
  return [["step", step], ["S", String(frame.S)], ["C", String(frame.C)],
    ["delivered", `${frame.delivered} / ${info.goodsTotal}`], ["T", formatT(info)]];
}

function sameCells(a, b) {
  if (a === b) return true;
  if (!a || !b || a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

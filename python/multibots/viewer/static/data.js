// MultiBots viewer: data. Decodes replay chunks (docs/replay-format.md) fetched from the
// server a few at a time, and the live stream's one-frame chunks.

// Event codes by name, from the engine's names in the server's meta (`event_names`).
let EV_PICKUP = -1, EV_RESTOCK = -1, EV_ASSIGN = -1, EV_DELIVER = -1, EV_PUT_BACK = -1;

/** Takes the engine's event names (`meta.event_names`: code -> name). */
export function setEventNames(eventNames) {
  for (const [code, name] of Object.entries(eventNames || {})) {
    if (name === "PICKUP") EV_PICKUP = Number(code);
    else if (name === "RESTOCK") EV_RESTOCK = Number(code);
    else if (name === "ASSIGN") EV_ASSIGN = Number(code);
    else if (name === "DELIVER") EV_DELIVER = Number(code);
    else if (name === "PUT_BACK") EV_PUT_BACK = Number(code);
  }
}

// The codec's numbers (docs/replay-format.md), from the engine through the server's meta
// (`codec`): the state byte's "marked to charge" flag and state-code bits, the heading steps
// in a turn and the energy word of a full battery. The page holds no copy of them.
export const CODEC = { marked: 0, stateMask: 0, headingSteps: 0, energyScale: 0 };
const CODEC_KEYS = {
  marked: "marked", stateMask: "state_mask", headingSteps: "heading_steps", energyScale: "energy_scale",
};

/** Takes the engine's codec numbers (`meta.codec`); throws if one is missing. */
export function setCodec(codec) {
  for (const [key, name] of Object.entries(CODEC_KEYS)) {
    const v = (codec || {})[name];
    if (!Number.isInteger(v) || v <= 0) throw new Error(`the server sent no codec.${name}`);
    CODEC[key] = v;
  }
}

/** A state byte's state code. */
export function stateCode(b) { return b & CODEC.stateMask; }
/** Whether a state byte says "marked to charge". */
export function isMarked(b) { return (b & CODEC.marked) !== 0; }
/** A heading byte as an angle, radians. */
export function headingAngle(b) { return b * (2 * Math.PI / CODEC.headingSteps); }
/** An energy word as a fraction of a full battery. */
export function energyFraction(w) { return w / CODEC.energyScale; }

function align(pos, size) { return Math.ceil(pos / size) * size; }

/** Decode a decompressed chunk (ArrayBuffer) into typed-array views (no copies). */
export function decodeChunk(buf) {
  if (buf.byteLength < 16) throw new Error(`chunk too short (${buf.byteLength} bytes)`);
  const head = new Uint32Array(buf, 0, 4);
  const first = head[0], k = head[1], n = head[2], e = head[3];
  let pos = 16;
  const take = (Type, count) => {
    pos = align(pos, Type.BYTES_PER_ELEMENT);
    const end = pos + count * Type.BYTES_PER_ELEMENT;
    if (end > buf.byteLength) throw new Error("chunk is truncated");
    const arr = new Type(buf, pos, count);
    pos = end;
    return arr;
  };
  const counters = take(Uint32Array, 3 * k);
  const x = take(Float32Array, k * n);
  const y = take(Float32Array, k * n);
  const events = take(Uint32Array, 4 * e);
  const energy = take(Uint16Array, k * n);
  const heading = take(Uint8Array, k * n);
  const state = take(Uint8Array, k * n);
  // People (docs/people.md): whatever follows, 8 bytes per person and frame.
  const rest = buf.byteLength - pos;
  const p = k > 0 ? rest / (8 * k) : 0;
  if (!Number.isInteger(p)) throw new Error("chunk has a partial people section");
  const px = take(Float32Array, k * p);
  const py = take(Float32Array, k * p);
  return { first, count: k, n, nEvents: e, counters, x, y, events, energy, heading, state, p, px, py,
           bytes: buf.byteLength };
}

/** The frame at index k of a decoded chunk: subarray views. */
export function frameOf(ch, k) {
  const n = ch.n, a = k * n, b = a + n;
  return {
    step: ch.first + k,
    x: ch.x.subarray(a, b), y: ch.y.subarray(a, b),
    heading: ch.heading.subarray(a, b), state: ch.state.subarray(a, b),
    energy: ch.energy.subarray(a, b),
    S: ch.counters[3 * k], C: ch.counters[3 * k + 1], delivered: ch.counters[3 * k + 2],
    hx: ch.px.subarray(k * ch.p, (k + 1) * ch.p), hy: ch.py.subarray(k * ch.p, (k + 1) * ch.p),
  };
}

export class ReplaySource {
  constructor(meta, cacheBytes = 160 * 1024 * 1024) {
    this.meta = meta;
    this.frames = meta.frames;
    this.chunks = meta.chunks;  // [[first_frame, frames], ...]
    this.firsts = meta.chunks.map((c) => c[0]);
    this.cache = new Map();      // index -> decoded chunk (insertion order = LRU)
    this.pending = new Map();    // index -> promise
    this.cacheBytes = cacheBytes;  // decoded chunks kept, by size (at least the last three)
    this.cellsKey = null; this.cellsVal = null;
    this.failed = null;
  }

  chunkIndex(f) {
    let lo = 0, hi = this.firsts.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.firsts[mid] <= f) lo = mid; else hi = mid - 1;
    }
    return lo;
  }

  has(i) { return this.cache.has(i); }

  load(i) {
    if (i < 0 || i >= this.chunks.length) return Promise.resolve(null);
    if (this.cache.has(i)) {
      const ch = this.cache.get(i);
      this.cache.delete(i); this.cache.set(i, ch);
      return Promise.resolve(ch);
    }
    if (this.pending.has(i)) return this.pending.get(i);
    const p = Promise.all([
      fetch(`/api/chunk/${i}`).then((r) => { if (!r.ok) throw new Error(`chunk ${i}: HTTP ${r.status}`); return r.arrayBuffer(); }),
      fetch(`/api/base/${i}`).then((r) => { if (!r.ok) throw new Error(`base ${i}: HTTP ${r.status}`); return r.json(); }),
    ]).then(([buf, base]) => {
      const ch = decodeChunk(buf);
      ch.baseCells = Uint8Array.from(base.cells);
      // A grid replay (docs/lorr.md): each robot's goal cell before the chunk's events, or -1.
      ch.baseGoals = base.goals ? Int32Array.from(base.goals) : null;
      this.cache.set(i, ch);
      let total = 0;
      for (const c of this.cache.values()) total += c.bytes;
      while (this.cache.size > 3 && total > this.cacheBytes) {
        const oldest = this.cache.keys().next().value;
        total -= this.cache.get(oldest).bytes;
        this.cache.delete(oldest);
      }
      this.pending.delete(i);
      return ch;
    }).catch((err) => { this.pending.delete(i); this.failed = String(err); throw err; });
    this.pending.set(i, p);
    return p;
  }

  /** The frame f if its chunk is loaded (else null, and the chunk is requested). */
  frame(f) {
    const i = this.chunkIndex(f);
    const ch = this.cache.get(i);
    if (!ch) { this.load(i).catch(() => {}); return null; }
    return frameOf(ch, f - ch.first);
  }

  async frameAsync(f) {
    const i = this.chunkIndex(f);
    const ch = await this.load(i);
    return frameOf(ch, f - ch.first);
  }

  /** Each robot's goal cell after step f in a grid replay (needs f's chunk loaded). */
  goals(f) { return goalsAt(this.cache.get(this.chunkIndex(f)), f); }

  /** Which cells hold goods after step f (needs f's chunk loaded). */
  cells(f) {
    const i = this.chunkIndex(f);
    const ch = this.cache.get(i);
    if (!ch) return null;
    const ev = ch.events;
    let m = 0;
    while (m < ch.nEvents && ev[4 * m] <= f) m++;
    const key = i * 1e9 + m;
    if (this.cellsKey === key && this.cellsCh === ch) return this.cellsVal;
    const cells = Uint8Array.from(ch.baseCells);
    for (let j = 0; j < m; j++) {
      const kind = ev[4 * j + 1], cell = ev[4 * j + 3];
      if (cell >= cells.length) continue;
      if (kind === EV_PICKUP) cells[cell] = 0;
      else if (kind === EV_RESTOCK) cells[cell] = 1;
    }
    this.cellsKey = key; this.cellsCh = ch; this.cellsVal = cells;
    return cells;
  }
}

/** Each robot's goal cell after step f in a grid replay (-1: none), from the chunk's
 * starting goals and its ASSIGN, DELIVER and PUT_BACK events; null if f's chunk is not
 * loaded or the replay has no goals. */
export function goalsAt(ch, f) {
  if (!ch || !ch.baseGoals) return null;
  const ev = ch.events;
  let m = 0;
  while (m < ch.nEvents && ev[4 * m] <= f) m++;
  if (ch.goalsKey === m) return ch.goalsVal;
  const goals = Int32Array.from(ch.baseGoals);
  for (let j = 0; j < m; j++) {
    const kind = ev[4 * j + 1], robot = ev[4 * j + 2];
    if (robot >= goals.length) continue;
    if (kind === EV_ASSIGN) goals[robot] = ev[4 * j + 3];
    else if (kind === EV_DELIVER || kind === EV_PUT_BACK) goals[robot] = -1;
  }
  ch.goalsKey = m; ch.goalsVal = goals;
  return goals;
}

function b64bytes(s) {
  const bin = atob(s);
  const out = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
  return out;
}

export class LiveSource {
  constructor(meta, onMessage) {
    this.meta = meta;
    this.latest = null;   // {frame, cells, msg}
    this.onMessage = onMessage;
    this.connected = false;
    this.es = new EventSource("/api/stream");
    this.es.onopen = () => { this.connected = true; };
    this.es.onerror = () => { this.connected = false; };
    this.es.onmessage = (ev) => {
      let msg;
      try { msg = JSON.parse(ev.data); } catch (e) { return; }
      const bytes = b64bytes(msg.frame);
      const ch = decodeChunk(bytes.buffer);
      this.latest = { frame: frameOf(ch, 0), cells: b64bytes(msg.cells), msg };
      if (this.onMessage) this.onMessage(this.latest);
    };
  }

  async control(action, speed) {
    const body = speed === undefined ? { action } : { action, speed };
    const r = await fetch("/api/control", {
      method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
    });
    if (!r.ok) throw new Error(`control: HTTP ${r.status}`);
    return r.json();
  }

  close() { this.es.close(); }
}

/** The robots queued at each resource in frame f, from each one's queue as the replay's
 * footer keeps it: [frame, robots, frame, robots, ...] where it changed (docs/replay-format.md). */
export function queuesAt(changes, f) {
  return (changes || []).map((c) => {
    let lo = 0, hi = c.length / 2 - 1, k = -1;
    while (lo <= hi) {
      const mid = (lo + hi) >> 1;
      if (c[2 * mid] <= f) { k = mid; lo = mid + 1; } else hi = mid - 1;
    }
    return k < 0 ? 0 : c[2 * k + 1];
  });
}

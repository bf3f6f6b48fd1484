// What the page knows: the scene, the latest frame, trails, recent messages, metric history.

const TRAIL_POINTS = 240;
const MESSAGES_KEPT = 400;
const LOG_KEPT = 200;

export class State {
  constructor() {
    this.hello = null;
    this.scene = null;
    this.frame = null;
    this.status = null;
    this.byId = new Map(); // id -> entity of the latest frame
    this.trails = new Map(); // id -> [[x, y, z], ...]
    this.messages = []; // recent MessageEvents, newest last
    this.log = []; // [t_ns, line]
    this.history = { t_ns: [], values: {} };
    this.selected = null; // entity id
    this.frames = 0; // frames received
    this.listeners = [];
  }

  /** Calls f(kind) on every change: 'hello', 'scene', 'frame', 'status', 'select', 'history'. */
  on(f) {
    this.listeners.push(f);
  }

  emit(kind) {
    for (const f of this.listeners) f(kind);
  }

  handle(msg) {
    switch (msg.type) {
      case 'hello':
        this.hello = msg;
        this.emit('hello');
        break;
      case 'scene':
        this.scene = msg.scene;
        this.emit('scene');
        break;
      case 'history':
        this.history = { t_ns: msg.t_ns, values: msg.values };
        this.emit('history');
        break;
      case 'frame':
        this.addFrame(msg.frame);
        this.emit('frame');
        break;
      case 'status':
        this.status = msg;
        this.emit('status');
        break;
      case 'error':
        console.warn('server:', msg.message);
        break;
      default:
        console.warn('unknown message', msg.type);
    }
  }

  addFrame(f) {
    const back = this.frame && f.t_ns < this.frame.t_ns;
    if (back) {
      // A seek backwards: the past shown so far no longer leads here.
      this.trails.clear();
      this.messages = [];
      this.log = [];
    }
    this.frame = f;
    this.frames += 1;
    this.byId = new Map(f.entities.map((e) => [e.id, e]));
    for (const e of f.entities) {
      let trail = this.trails.get(e.id);
      if (!trail) this.trails.set(e.id, (trail = []));
      const last = trail[trail.length - 1];
      if (!last || last[0] !== e.pos[0] || last[1] !== e.pos[1] || last[2] !== e.pos[2]) trail.push(e.pos);
      if (trail.length > TRAIL_POINTS) trail.splice(0, trail.length - TRAIL_POINTS);
    }
    for (const id of this.trails.keys()) if (!this.byId.has(id)) this.trails.delete(id);
    this.messages.push(...f.messages);
    if (this.messages.length > MESSAGES_KEPT) this.messages.splice(0, this.messages.length - MESSAGES_KEPT);
    for (const line of f.log) this.log.push([f.t_ns, line]);
    if (this.log.length > LOG_KEPT) this.log.splice(0, this.log.length - LOG_KEPT);
    this.pushHistory(f);
  }

  pushHistory(f) {
    const h = this.history;
    const n = h.t_ns.length;
    if (n && h.t_ns[n - 1] >= f.t_ns) {
      if (h.t_ns[n - 1] > f.t_ns && this.hello && this.hello.mode === 'live') this.history = { t_ns: [], values: {} };
      return;
    }
    h.t_ns.push(f.t_ns);
    for (const [name, v] of Object.entries(f.metrics)) {
      if (!h.values[name]) h.values[name] = new Array(n).fill(null);
      h.values[name].push(v);
    }
    for (const col of Object.values(h.values)) while (col.length < n + 1) col.push(null);
  }

  select(id) {
    this.selected = id;
    this.emit('select');
  }

  intentionOf(id) {
    return this.frame ? this.frame.intentions.find((i) => i.id === id) : undefined;
  }
}

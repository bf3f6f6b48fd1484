// Time controls: pause / resume, single step, speed ladder, clock, and the replay timeline.

import { clock, speed as speedText, wallClock } from './format.js';

/** The speed factors offered by − and +. */
export const SPEEDS = [0.1, 0.25, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500, 1000];

export class Controls {
  /** @param {import('./state.js').State} state @param {import('./net.js').Connection} net */
  constructor(state, net) {
    this.state = state;
    this.net = net;
    this.$ = (id) => document.getElementById(id);
    this.seeking = false;
    this.$('play').addEventListener('click', () => this.togglePause());
    this.$('step').addEventListener('click', () => this.net.send({ cmd: 'step', n: 1 }));
    this.$('slower').addEventListener('click', () => this.nudge(-1));
    this.$('faster').addEventListener('click', () => this.nudge(1));
    const tl = this.$('timeline');
    tl.addEventListener('input', () => {
      this.seeking = true;
      this.seek(Number(tl.value) / 1000);
    });
    tl.addEventListener('change', () => {
      this.seeking = false;
    });
    document.addEventListener('keydown', (e) => {
      if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) return;
      if (e.key === ' ') {
        e.preventDefault();
        this.togglePause();
      } else if (e.key === '.') this.net.send({ cmd: 'step', n: 1 });
      else if (e.key === '+' || e.key === '=') this.nudge(1);
      else if (e.key === '-') this.nudge(-1);
    });
  }

  togglePause() {
    const s = this.state.status;
    this.net.send({ cmd: s && s.paused ? 'resume' : 'pause' });
  }

  nudge(dir) {
    const s = this.state.status;
    const now = s && s.speed != null ? s.speed : 1;
    let i = SPEEDS.findIndex((v) => v >= now - 1e-9);
    if (i < 0) i = SPEEDS.length - 1;
    if (dir > 0 && SPEEDS[i] <= now + 1e-9) i += 1;
    if (dir < 0) i -= 1;
    i = Math.max(0, Math.min(SPEEDS.length - 1, i));
    this.net.send({ cmd: 'speed', factor: SPEEDS[i] });
  }

  seek(fraction) {
    const h = this.state.hello;
    if (!h || h.end_ns == null) return;
    const t = Math.round(h.start_ns + fraction * (h.end_ns - h.start_ns));
    this.net.send({ cmd: 'seek', t_ns: t });
  }

  onHello() {
    const h = this.state.hello;
    const replay = h.mode === 'replay';
    this.$('mode').textContent = h.mode;
    this.$('mode').className = `badge ${h.mode}`;
    this.$('title').textContent = h.title;
    document.title = `${h.title} · Vitro view`;
    this.$('timeline-bar').hidden = !replay;
    this.$('step').title = replay ? 'pause, then show the next frame (.)' : 'pause, then fire exactly one event (.)';
    if (replay) this.$('span').textContent = `${clock(h.start_ns)} – ${clock(h.end_ns)}`;
  }

  onFrame() {
    const f = this.state.frame;
    this.$('clock').textContent = clock(f.t_ns);
    this.$('wall').textContent = wallClock(this.state.scene?.start_unix_ms, f.t_ns);
    this.$('events').textContent = `${f.events} events`;
    this.$('clock').dataset.tNs = String(f.t_ns);
    this.$('events').dataset.events = String(f.events);
    const h = this.state.hello;
    if (h && h.mode === 'replay' && h.end_ns > h.start_ns && !this.seeking) {
      this.$('timeline').value = String(Math.round((1000 * (f.t_ns - h.start_ns)) / (h.end_ns - h.start_ns)));
    }
  }

  onStatus() {
    const s = this.state.status;
    this.$('play').textContent = s.paused ? 'Resume' : 'Pause';
    this.$('play').dataset.paused = String(s.paused);
    this.$('speed').textContent = speedText(s.speed);
    this.$('speed').dataset.speed = String(s.speed);
    let note = '';
    if (s.failure) note = `failed: ${s.failure}`;
    else if (s.finished && this.state.hello && this.state.hello.mode === 'live') note = `run over · trace ${s.trace_hash}`;
    else if (s.finished) note = 'end of recording';
    else if (s.paused) note = 'paused';
    this.$('runstate').textContent = note;
  }

  onConnection(up) {
    if (!up) {
      this.$('mode').textContent = 'disconnected';
      this.$('mode').className = 'badge';
    }
  }
}

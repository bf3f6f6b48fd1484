// Charts of the mission metrics over simulated time: one small line chart per metric.

import { clock, esc, num } from './format.js';

export class Charts {
  constructor(el, state) {
    this.el = el;
    this.state = state;
    this.names = '';
    this.canvases = new Map();
  }

  update() {
    const h = this.state.history;
    const names = Object.keys(h.values).sort();
    if (!names.length) return;
    if (names.join('\n') !== this.names) this.build(names);
    const cursor = this.state.frame ? this.state.frame.t_ns : null;
    for (const name of names) {
      const { canvas, value } = this.canvases.get(name);
      const col = h.values[name];
      let last = null;
      for (let i = col.length - 1; i >= 0 && last == null; i--) last = col[i];
      // in a replay the value at the playhead, live the latest
      const atCursor = this.valueAt(name, cursor);
      value.textContent = num(atCursor != null ? atCursor : last);
      draw(canvas, h.t_ns, col, cursor);
    }
  }

  valueAt(name, t) {
    if (t == null) return null;
    const h = this.state.history;
    let v = null;
    for (let i = 0; i < h.t_ns.length && h.t_ns[i] <= t; i++) if (h.values[name][i] != null) v = h.values[name][i];
    return v;
  }

  build(names) {
    this.names = names.join('\n');
    this.canvases.clear();
    this.el.textContent = '';
    for (const name of names) {
      const div = document.createElement('div');
      div.className = 'chart';
      div.innerHTML = `<div class="head"><span>${esc(name.replace(/_/g, ' '))}</span><b></b></div><canvas></canvas>`;
      this.el.append(div);
      this.canvases.set(name, { canvas: div.querySelector('canvas'), value: div.querySelector('b') });
    }
  }
}

function draw(canvas, ts, vs, cursor) {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth || 300;
  const h = canvas.clientHeight || 46;
  if (canvas.width !== Math.round(w * dpr)) canvas.width = Math.round(w * dpr);
  if (canvas.height !== Math.round(h * dpr)) canvas.height = Math.round(h * dpr);
  const ctx = canvas.getContext('2d');
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  if (ts.length < 1) return;
  const t0 = ts[0];
  const t1 = Math.max(ts[ts.length - 1], t0 + 1);
  let lo = Infinity;
  let hi = -Infinity;
  for (const v of vs) {
    if (v == null) continue;
    lo = Math.min(lo, v);
    hi = Math.max(hi, v);
  }
  if (!Number.isFinite(lo)) return;
  if (hi === lo) {
    hi += 1;
    lo -= lo === 0 ? 0 : 1;
  }
  const X = (t) => 2 + ((t - t0) / (t1 - t0)) * (w - 4);
  const Y = (v) => h - 4 - ((v - lo) / (hi - lo)) * (h - 16);
  ctx.strokeStyle = '#1f6fb2';
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  let pen = false;
  for (let i = 0; i < ts.length; i++) {
    if (vs[i] == null) {
      pen = false;
      continue;
    }
    if (pen) ctx.lineTo(X(ts[i]), Y(vs[i]));
    else ctx.moveTo(X(ts[i]), Y(vs[i]));
    pen = true;
  }
  ctx.stroke();
  ctx.fillStyle = '#7a858f';
  ctx.font = '9px system-ui, sans-serif';
  ctx.textBaseline = 'top';
  ctx.textAlign = 'left';
  ctx.fillText(num(hi), 3, 1);
  ctx.textAlign = 'right';
  ctx.fillText(clock(t1), w - 3, 1);
  if (cursor != null && cursor >= t0 && cursor <= t1) {
    ctx.strokeStyle = 'rgba(200,60,0,0.7)';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(X(cursor), 0);
    ctx.lineTo(X(cursor), h);
    ctx.stroke();
  }
}

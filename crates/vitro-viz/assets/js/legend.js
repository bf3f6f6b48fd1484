// The legend over the map: what the symbols, colours and lines mean (only what is shown).

import { layers } from './layers.js';
import { KIND_NAMES, SIDES, symbolCanvas } from './symbols.js';

function sample(draw, w = 26, h = 14) {
  const c = document.createElement('canvas');
  const dpr = window.devicePixelRatio || 1;
  c.width = w * dpr;
  c.height = h * dpr;
  c.style.width = `${w}px`;
  c.style.height = `${h}px`;
  const ctx = c.getContext('2d');
  ctx.scale(dpr, dpr);
  draw(ctx, w, h);
  return c;
}

function stroke(color, width, dash = [], casing = null) {
  return sample((ctx, w, h) => {
    ctx.lineCap = 'round';
    if (casing) {
      ctx.strokeStyle = casing;
      ctx.lineWidth = width + 2;
      ctx.beginPath();
      ctx.moveTo(3, h / 2);
      ctx.lineTo(w - 3, h / 2);
      ctx.stroke();
    }
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.setLineDash(dash);
    ctx.beginPath();
    ctx.moveTo(3, h / 2);
    ctx.lineTo(w - 3, h / 2);
    ctx.stroke();
  });
}

function area(fill, edge) {
  return sample((ctx, w, h) => {
    ctx.fillStyle = fill;
    ctx.strokeStyle = edge;
    ctx.fillRect(4, 2, w - 8, h - 4);
    ctx.strokeRect(4, 2, w - 8, h - 4);
  });
}

function dots(rgb) {
  return sample((ctx, w, h) => {
    [[7, 7, 3, 0.3], [14, 6, 5, 0.6], [20, 8, 3, 0.4]].forEach(([x, y, r, a]) => {
      ctx.fillStyle = `rgba(${rgb},${a})`;
      ctx.beginPath();
      ctx.arc(x, y, r, 0, Math.PI * 2);
      ctx.fill();
    });
  });
}

function item(canvas, text) {
  const d = document.createElement('div');
  d.className = 'item';
  d.append(canvas, document.createTextNode(text));
  return d;
}

function column(title, items) {
  const col = document.createElement('div');
  const h = document.createElement('h3');
  h.textContent = title;
  col.append(h, ...items);
  return col;
}

/** Rebuilds the legend when what it must explain changes. */
export class Legend {
  constructor(el, state) {
    this.el = el;
    this.state = state;
    this.key = '';
  }

  update() {
    const st = this.state;
    const s = st.scene;
    if (!s) return;
    const f = st.frame;
    const kinds = [...new Set([...st.byId.values()].map((e) => e.kind))].sort();
    const has = {
      los: f && f.detections.length > 0,
      sensors: f && f.sensors && f.sensors.length > 0,
      plan: f && f.intentions.some((i) => i.path && i.path.length),
      orig: f && f.intentions.some((i) => i.original_path && i.original_path.length),
      heat: f && f.intentions.some((i) => i.heat && i.heat.length),
      belief: f && f.intentions.some((i) => i.belief && i.belief.length),
    };
    const unseen = [...st.byId.values()].some((e) => e.status === 'undetected');
    const key = JSON.stringify([kinds, has, layers, unseen]);
    if (key === this.key) return;
    this.key = key;

    const sides = SIDES.map((side) => item(symbolCanvas(side, 'none', 18), side));
    if ([...st.byId.values()].some((e) => e.status === 'undetected')) {
      sides.push(item(symbolCanvas('hostile', 'none', 18, 'undetected'), 'not yet detected'));
    }
    const types = kinds.map((k) => item(symbolCanvas('friendly', k, 18), KIND_NAMES[k] || k));
    const map = [];
    if (s.streets.length) map.push(item(stroke('#fff', 4, [], '#8f959c'), 'street'));
    if (s.paths.length) map.push(item(stroke('#9a7b52', 1.2, [3, 3]), 'footpath'));
    if (s.bridges.length) map.push(item(stroke('#e8d9a8', 5, [], '#3b3b3b'), 'bridge'));
    if (s.buildings.length) map.push(item(area('#a08f80', '#5b4f45'), 'building (darker: taller)'));
    if (s.forbidden.length) map.push(item(area('rgba(200,30,30,0.25)', 'rgba(190,30,30,0.7)'), 'forbidden zone'));
    if (Object.keys(s.places).length) map.push(item(sample((ctx) => starMini(ctx)), 'mission place'));
    const over = [item(stroke('#00557a', 1.6), 'trail (recent track)')];
    over.push(item(stroke('#111', 1.5), 'heading'));
    if (has.los) over.push(item(stroke('#a00000', 1.5, [5, 3]), 'line of sight (colour: side seen as)'));
    if (has.sensors) over.push(item(area('rgba(40,140,255,0.15)', 'rgba(20,90,200,0.5)'), 'sensor footprint'));
    if (has.plan) over.push(item(stroke('#7b2fb5', 2.5), 'planned path (selected)'));
    if (has.orig) over.push(item(stroke('#5a5a5a', 2, [6, 5]), 'original plan, before repair'));
    if (has.heat) over.push(item(dots('240,120,0'), 'patrol policy (visit probability)'));
    if (has.belief) over.push(item(dots('150,40,200'), 'belief: where the evader may be'));

    const cols = document.createElement('div');
    cols.className = 'cols';
    cols.append(column('Side', sides));
    if (types.length) cols.append(column('Type', types));
    if (map.length) cols.append(column('Map', map));
    cols.append(column('Overlays', over));
    this.el.replaceChildren(cols);
  }
}

function starMini(ctx) {
  ctx.beginPath();
  for (let i = 0; i < 10; i++) {
    const a = -Math.PI / 2 + (i * Math.PI) / 5;
    const r = i % 2 ? 2.6 : 6;
    ctx.lineTo(13 + r * Math.cos(a), 7 + r * Math.sin(a));
  }
  ctx.closePath();
  ctx.fillStyle = '#9b59d0';
  ctx.fill();
}


// The moving layers of the 2D map, drawn on each frame: minds (heat, belief, plans), sensors,
// trails, messages, lines of sight, entities, labels, scale.

import { layers } from './layers.js';
import { drawSymbol, isAir, STROKE } from './symbols.js';
import { aboveGround } from './terrain.js';

const SYMBOL = 9; // symbol half-size, pixels
const MESSAGE_SHOWN_NS = 2e9; // messages stay on the map this long (simulated)

function path(ctx, map, pts) {
  ctx.beginPath();
  pts.forEach((p, i) => {
    const [x, y] = map.toScreen(p);
    if (i) ctx.lineTo(x, y);
    else ctx.moveTo(x, y);
  });
}

/** Weighted places as discs, darker and larger for heavier weights. */
function weights(ctx, map, cells, rgb) {
  let max = 0;
  for (const [, w] of cells) max = Math.max(max, w);
  if (!(max > 0)) return;
  for (const [p, w] of cells) {
    const k = w / max;
    if (k < 0.02) continue;
    const [x, y] = map.toScreen(p);
    const r = 5 + 11 * Math.sqrt(k);
    ctx.beginPath();
    ctx.arc(x, y, r, 0, Math.PI * 2);
    ctx.fillStyle = `rgba(${rgb},${0.15 + 0.6 * k})`;
    ctx.fill();
  }
}

function minds(ctx, map, st) {
  const f = st.frame;
  for (const it of f.intentions) {
    const mine = it.id === st.selected;
    if (layers.heat && it.heat && it.heat.length && (mine || st.selected == null)) weights(ctx, map, it.heat, '240,120,0');
    if (layers.belief && it.belief && it.belief.length && (mine || st.selected == null)) weights(ctx, map, it.belief, '150,40,200');
  }
  for (const it of f.intentions) {
    if (!(layers.intentions || it.id === st.selected)) continue;
    ctx.lineJoin = 'round';
    if (it.original_path && it.original_path.length > 1) {
      ctx.setLineDash([6, 5]);
      ctx.strokeStyle = 'rgba(90,90,90,0.85)';
      ctx.lineWidth = 2;
      path(ctx, map, it.original_path);
      ctx.stroke();
    }
    if (it.path && it.path.length > 0) {
      const e = st.byId.get(it.id);
      const pts = e ? [e.pos, ...it.path] : it.path;
      ctx.setLineDash([]);
      ctx.strokeStyle = 'rgba(255,255,255,0.8)';
      ctx.lineWidth = 5;
      path(ctx, map, pts);
      ctx.stroke();
      ctx.strokeStyle = '#7b2fb5';
      ctx.lineWidth = 2.5;
      path(ctx, map, pts);
      ctx.stroke();
      const [gx, gy] = map.toScreen(pts[pts.length - 1]);
      ctx.beginPath();
      ctx.arc(gx, gy, 5, 0, Math.PI * 2);
      ctx.fillStyle = '#7b2fb5';
      ctx.fill();
    }
  }
  ctx.setLineDash([]);
}

function sensors(ctx, map, st) {
  for (const s of st.frame.sensors || []) {
    const e = st.byId.get(s.id);
    if (!e) continue;
    const mine = s.id === st.selected;
    if (!(layers.sensors || mine)) continue;
    const [x, y] = map.toScreen(e.pos);
    const r = s.range * map.view.scale;
    ctx.beginPath();
    if (s.fov >= Math.PI * 2 - 1e-6) {
      ctx.arc(x, y, r, 0, Math.PI * 2);
    } else {
      // canvas angles run clockwise (y down): negate the world heading
      ctx.moveTo(x, y);
      ctx.arc(x, y, r, -s.heading - s.fov / 2, -s.heading + s.fov / 2);
      ctx.closePath();
    }
    const rgb = e.side === 'hostile' ? '200,40,40' : '20,100,210';
    ctx.fillStyle = `rgba(${rgb},${mine ? 0.16 : 0.05})`;
    ctx.strokeStyle = `rgba(${rgb},${mine ? 0.8 : 0.3})`;
    ctx.lineWidth = mine ? 1.5 : 1;
    ctx.fill();
    ctx.stroke();
  }
}

function trails(ctx, map, st) {
  ctx.lineWidth = 1.6;
  for (const [id, pts] of st.trails) {
    const e = st.byId.get(id);
    if (!e || pts.length < 2) continue;
    ctx.strokeStyle = STROKE[e.side] || '#555';
    ctx.globalAlpha = 0.55;
    path(ctx, map, pts);
    ctx.stroke();
  }
  ctx.globalAlpha = 1;
}

function messages(ctx, map, st) {
  const now = st.frame.t_ns;
  for (const m of st.messages) {
    if (now - m.t_ns > MESSAGE_SHOWN_NS) continue;
    const a = st.byId.get(m.from);
    if (!a) continue;
    const [x0, y0] = map.toScreen(a.pos);
    ctx.strokeStyle = m.delivered ? 'rgba(0,130,90,0.8)' : 'rgba(200,30,30,0.8)';
    ctx.lineWidth = 1.2;
    ctx.setLineDash(m.delivered ? [] : [3, 3]);
    const b = m.to != null ? st.byId.get(m.to) : null;
    ctx.beginPath();
    if (b) {
      const [x1, y1] = map.toScreen(b.pos);
      ctx.moveTo(x0, y0);
      ctx.lineTo(x1, y1);
    } else {
      ctx.arc(x0, y0, 16, 0, Math.PI * 2);
    }
    ctx.stroke();
  }
  ctx.setLineDash([]);
}

function detections(ctx, map, st) {
  for (const d of st.frame.detections) {
    const [x0, y0] = map.toScreen(d.from);
    const [x1, y1] = map.toScreen(d.to);
    ctx.strokeStyle = STROKE[d.seen_as] || '#000';
    ctx.lineWidth = 1.5;
    ctx.setLineDash([5, 3]);
    ctx.beginPath();
    ctx.moveTo(x0, y0);
    ctx.lineTo(x1, y1);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.beginPath();
    ctx.arc(x1, y1, SYMBOL * 1.7, 0, Math.PI * 2);
    ctx.stroke();
  }
}

function entities(ctx, map, st) {
  const list = [...st.byId.values()];
  // passengers under their vehicle, aircraft over ground units, the selected entity on top
  const layer = (e) => (e.id === st.selected ? 2 : e.status === 'aboard' ? 0 : 1);
  list.sort((a, b) => layer(a) - layer(b) || a.pos[2] - b.pos[2]);
  for (const e of list) {
    const [x, y] = map.toScreen(e.pos);
    if (x < -40 || y < -40 || x > map.w + 40 || y > map.h + 40) continue;
    if (e.id === st.selected) {
      ctx.beginPath();
      ctx.arc(x, y, SYMBOL * 2.2, 0, Math.PI * 2);
      ctx.fillStyle = 'rgba(255,215,0,0.45)';
      ctx.fill();
      ctx.strokeStyle = '#c79a00';
      ctx.lineWidth = 2;
      ctx.stroke();
    }
    drawSymbol(ctx, x, y, SYMBOL, e.side, e.kind, e.speed > 0.05 ? e.heading : null, e.status);
    if (layers.labels) {
      ctx.font = '11px system-ui, sans-serif';
      ctx.textAlign = 'left';
      ctx.textBaseline = 'middle';
      ctx.lineWidth = 3;
      ctx.strokeStyle = 'rgba(255,255,255,0.85)';
      const label = isAir(e.kind) ? `${e.name} ${Math.round(aboveGround(st.scene.terrain, e.pos))} m` : e.name;
      ctx.strokeText(label, x + SYMBOL * 1.5 + 2, y + SYMBOL + 2);
      ctx.fillStyle = '#111';
      ctx.fillText(label, x + SYMBOL * 1.5 + 2, y + SYMBOL + 2);
    }
  }
}

/** A scale bar (a round number of metres) and a north arrow, bottom right. */
function scale(ctx, map) {
  const target = 120 / map.view.scale;
  const p = 10 ** Math.floor(Math.log10(target));
  const m = [1, 2, 5, 10].map((k) => k * p).filter((v) => v <= target).pop() || p;
  const w = m * map.view.scale;
  const x = map.w - 20 - w;
  const y = map.h - 34;
  ctx.fillStyle = 'rgba(255,255,255,0.85)';
  ctx.fillRect(x - 6, y - 16, w + 12, 26);
  ctx.strokeStyle = '#111';
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(x, y - 4);
  ctx.lineTo(x, y);
  ctx.lineTo(x + w, y);
  ctx.lineTo(x + w, y - 4);
  ctx.stroke();
  ctx.fillStyle = '#111';
  ctx.font = '11px system-ui, sans-serif';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'alphabetic';
  ctx.fillText(m >= 1000 ? `${m / 1000} km` : `${m} m`, x + w / 2, y - 5);
  const nx = map.w - 24;
  const ny = 26;
  ctx.beginPath();
  ctx.moveTo(nx, ny - 14);
  ctx.lineTo(nx + 7, ny + 6);
  ctx.lineTo(nx, ny + 1);
  ctx.lineTo(nx - 7, ny + 6);
  ctx.closePath();
  ctx.fill();
  ctx.font = 'bold 11px system-ui, sans-serif';
  ctx.fillText('N', nx, ny + 19);
}

/** Draws every moving layer of the latest frame. */
export function drawDynamic(ctx, map) {
  const st = map.state;
  if (st.frame && st.scene) {
    minds(ctx, map, st);
    sensors(ctx, map, st);
    if (layers.trails) trails(ctx, map, st);
    if (layers.messages) messages(ctx, map, st);
    if (layers.detections) detections(ctx, map, st);
    entities(ctx, map, st);
  }
  if (st.scene) scale(ctx, map);
}

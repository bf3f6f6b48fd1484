// The 2D map: a canvas with the static layers (terrain, streets, buildings...) cached and the
// moving ones (entities, lines of sight, plans) redrawn when a frame comes.

import { layers } from './layers.js';
import { drawDynamic } from './overlays.js';

export class Map2D {
  /** @param {HTMLCanvasElement} canvas @param {import('./state.js').State} state */
  constructor(canvas, state) {
    this.canvas = canvas;
    this.state = state;
    this.ctx = canvas.getContext('2d');
    this.view = { cx: 0, cy: 0, scale: 1 }; // world centre, pixels per metre
    this.staticLayer = document.createElement('canvas');
    this.staticDirty = true;
    this.dirty = true;
    this.terrainImage = null;
    this.follow = null;
    this.visible = true;
    this.dpr = 1;
    this.resize();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.interact();
    const loop = () => {
      if (this.dirty && this.visible) this.draw();
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  resize() {
    const r = this.canvas.getBoundingClientRect();
    this.dpr = window.devicePixelRatio || 1;
    this.w = Math.max(1, r.width);
    this.h = Math.max(1, r.height);
    this.canvas.width = Math.round(this.w * this.dpr);
    this.canvas.height = Math.round(this.h * this.dpr);
    this.staticLayer.width = this.canvas.width;
    this.staticLayer.height = this.canvas.height;
    this.invalidate(true);
  }

  invalidate(staticToo = false) {
    this.dirty = true;
    if (staticToo) this.staticDirty = true;
  }

  /** Frames the whole scene. */
  fit() {
    const s = this.state.scene;
    if (!s) return;
    const [x0, y0, x1, y1] = s.extent;
    this.view.cx = (x0 + x1) / 2;
    this.view.cy = (y0 + y1) / 2;
    this.view.scale = 0.92 * Math.min(this.w / Math.max(1, x1 - x0), this.h / Math.max(1, y1 - y0));
    this.invalidate(true);
  }

  /**
   * Frames the world box [x0, y0, x1, y1] (e.g. where the entities are) in the canvas, above
   * `insetBottom` pixels (e.g. the legend's).
   */
  fitTo([x0, y0, x1, y1], insetBottom = 0) {
    const h = Math.max(1, this.h - insetBottom);
    this.view.scale = Math.min(this.w / Math.max(1, x1 - x0), h / Math.max(1, y1 - y0));
    this.view.cx = (x0 + x1) / 2;
    this.view.cy = (y0 + y1) / 2 - insetBottom / 2 / this.view.scale;
    this.invalidate(true);
  }

  /** World [x, y] to canvas pixels (CSS). */
  toScreen(p) {
    const v = this.view;
    return [(p[0] - v.cx) * v.scale + this.w / 2, this.h / 2 - (p[1] - v.cy) * v.scale];
  }

  toWorld(sx, sy) {
    const v = this.view;
    return [(sx - this.w / 2) / v.scale + v.cx, (this.h / 2 - sy) / v.scale + v.cy];
  }

  /** Page coordinates of an entity's symbol (for tests and tooltips), or null. */
  screenPos(id) {
    const e = this.state.byId.get(id);
    if (!e) return null;
    const [x, y] = this.toScreen(e.pos);
    const r = this.canvas.getBoundingClientRect();
    return { x: r.left + x, y: r.top + y };
  }

  setScene() {
    this.terrainImage = terrainImage(this.state.scene.terrain);
    this.fit();
  }

  interact() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener('pointerdown', (e) => {
      drag = { x: e.offsetX, y: e.offsetY, moved: false };
      c.setPointerCapture(e.pointerId);
    });
    c.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const dx = e.offsetX - drag.x;
      const dy = e.offsetY - drag.y;
      if (!drag.moved && Math.hypot(dx, dy) < 4) return;
      drag.moved = true;
      c.classList.add('dragging');
      this.view.cx -= dx / this.view.scale;
      this.view.cy += dy / this.view.scale;
      drag.x = e.offsetX;
      drag.y = e.offsetY;
      this.invalidate(true);
    });
    c.addEventListener('pointerup', (e) => {
      c.classList.remove('dragging');
      if (drag && !drag.moved) this.pick(e.offsetX, e.offsetY);
      drag = null;
    });
    c.addEventListener(
      'wheel',
      (e) => {
        e.preventDefault();
        const before = this.toWorld(e.offsetX, e.offsetY);
        const f = Math.exp(-e.deltaY * 0.0015);
        this.view.scale = Math.min(200, Math.max(0.005, this.view.scale * f));
        const after = this.toWorld(e.offsetX, e.offsetY);
        this.view.cx += before[0] - after[0];
        this.view.cy += before[1] - after[1];
        this.invalidate(true);
      },
      { passive: false },
    );
  }

  /** Selects the entity nearest to a click (within 16 px), or nobody. */
  pick(sx, sy) {
    let best = null;
    let bestD = 16;
    for (const e of this.state.byId.values()) {
      const [x, y] = this.toScreen(e.pos);
      const d = Math.hypot(x - sx, y - sy);
      if (d < bestD) {
        best = e.id;
        bestD = d;
      }
    }
    this.state.select(best);
  }

  draw() {
    this.dirty = false;
    if (this.follow != null) {
      const e = this.state.byId.get(this.follow);
      if (e && (e.pos[0] !== this.view.cx || e.pos[1] !== this.view.cy)) {
        this.view.cx = e.pos[0];
        this.view.cy = e.pos[1];
        this.staticDirty = true;
      }
    }
    if (this.staticDirty) {
      this.staticDirty = false;
      const sctx = this.staticLayer.getContext('2d');
      sctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
      drawStatic(sctx, this);
    }
    const ctx = this.ctx;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.drawImage(this.staticLayer, 0, 0);
    ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    drawDynamic(ctx, this);
  }
}

/** Hill shading with a height tint, one pixel per terrain sample (row 0 at the top = north). */
function terrainImage(t) {
  if (!t || t.nx < 2 || t.ny < 2) return null;
  const { nx, ny, z, cell } = t;
  let lo = Infinity;
  let hi = -Infinity;
  for (const v of z) {
    lo = Math.min(lo, v);
    hi = Math.max(hi, v);
  }
  const c = document.createElement('canvas');
  c.width = nx;
  c.height = ny;
  const ctx = c.getContext('2d');
  const img = ctx.createImageData(nx, ny);
  const at = (i, j) => z[Math.min(ny - 1, Math.max(0, j)) * nx + Math.min(nx - 1, Math.max(0, i))];
  // Light from the north-west, 45° up.
  const L = [-0.5, 0.5, Math.SQRT1_2];
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const dzdx = (at(i + 1, j) - at(i - 1, j)) / (2 * cell);
      const dzdy = (at(i, j + 1) - at(i, j - 1)) / (2 * cell);
      const n = [-dzdx, -dzdy, 1];
      const len = Math.hypot(...n);
      const shade = Math.max(0, (n[0] * L[0] + n[1] * L[1] + n[2] * L[2]) / len);
      const h = hi > lo ? (at(i, j) - lo) / (hi - lo) : 0;
      // low: pale green, high: tan
      const base = [206 + 30 * h, 222 - 4 * h, 190 - 20 * h];
      const k = 0.55 + 0.55 * shade;
      const o = ((ny - 1 - j) * nx + i) * 4;
      img.data[o] = Math.min(255, base[0] * k);
      img.data[o + 1] = Math.min(255, base[1] * k);
      img.data[o + 2] = Math.min(255, base[2] * k);
      img.data[o + 3] = 255;
    }
  }
  ctx.putImageData(img, 0, 0);
  return c;
}

function line(ctx, map, pts) {
  ctx.beginPath();
  pts.forEach((p, i) => {
    const [x, y] = map.toScreen(p);
    if (i) ctx.lineTo(x, y);
    else ctx.moveTo(x, y);
  });
}

function ring(ctx, map, pts) {
  line(ctx, map, pts);
  ctx.closePath();
}

let hatch = null;
function hatchPattern(ctx) {
  if (hatch) return hatch;
  const c = document.createElement('canvas');
  c.width = c.height = 8;
  const h = c.getContext('2d');
  h.strokeStyle = 'rgba(200,30,30,0.55)';
  h.lineWidth = 1.2;
  h.beginPath();
  h.moveTo(0, 8);
  h.lineTo(8, 0);
  h.stroke();
  hatch = ctx.createPattern(c, 'repeat');
  return hatch;
}

function drawStatic(ctx, map) {
  ctx.fillStyle = '#f1efe8';
  ctx.fillRect(0, 0, map.w, map.h);
  const s = map.state.scene;
  if (!s) return;
  const px = map.view.scale; // pixels per metre
  const t = s.terrain;
  if (layers.terrain && map.terrainImage) {
    const [x0, y1] = map.toScreen([t.origin[0] - t.cell / 2, t.origin[1] + (t.ny - 0.5) * t.cell]);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(map.terrainImage, x0, y1, t.nx * t.cell * px, t.ny * t.cell * px);
  }
  if (layers.forbidden) {
    ctx.fillStyle = hatchPattern(ctx);
    ctx.strokeStyle = 'rgba(190,30,30,0.7)';
    ctx.lineWidth = 1;
    for (const z of s.forbidden) {
      ring(ctx, map, z);
      ctx.fill();
      ctx.stroke();
    }
  }
  if (layers.paths) {
    ctx.strokeStyle = '#9a7b52';
    ctx.lineWidth = 1;
    ctx.setLineDash([3, 3]);
    for (const p of s.paths) {
      line(ctx, map, p);
      ctx.stroke();
    }
    ctx.setLineDash([]);
  }
  if (layers.streets) {
    const w = Math.max(2, Math.min(14, 7 * px));
    ctx.lineCap = 'round';
    ctx.lineJoin = 'round';
    for (const [style, width] of [['#8f959c', w + 2], ['#ffffff', w]]) {
      ctx.strokeStyle = style;
      ctx.lineWidth = width;
      for (const st of s.streets) {
        line(ctx, map, st);
        ctx.stroke();
      }
    }
  }
  if (layers.bridges) {
    const w = Math.max(3, Math.min(16, 8 * px));
    ctx.lineCap = 'butt';
    for (const [style, width] of [['#3b3b3b', w + 4], ['#e8d9a8', w]]) {
      ctx.strokeStyle = style;
      ctx.lineWidth = width;
      for (const b of s.bridges) {
        line(ctx, map, b);
        ctx.stroke();
      }
    }
  }
  if (layers.buildings) {
    ctx.lineWidth = 0.8;
    ctx.strokeStyle = '#5b4f45';
    for (const b of s.buildings) {
      const k = Math.min(1, b.height / 30);
      ctx.fillStyle = `rgb(${196 - 80 * k},${176 - 78 * k},${160 - 76 * k})`;
      ring(ctx, map, b.footprint);
      ctx.fill();
      if (px > 0.35) ctx.stroke();
    }
  }
  if (layers.places) {
    ctx.font = 'bold 12px system-ui, sans-serif';
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    for (const [name, p] of Object.entries(s.places)) {
      const [x, y] = map.toScreen(p);
      star(ctx, x, y, 8);
      ctx.lineWidth = 3;
      ctx.strokeStyle = 'rgba(255,255,255,0.9)';
      ctx.strokeText(name, x + 10, y);
      ctx.fillStyle = '#5a2d82';
      ctx.fillText(name, x + 10, y);
    }
  }
}

/** A five-pointed star: a named place of the mission. */
export function star(ctx, x, y, r) {
  ctx.beginPath();
  for (let i = 0; i < 10; i++) {
    const a = -Math.PI / 2 + (i * Math.PI) / 5;
    const rr = i % 2 ? r * 0.45 : r;
    ctx.lineTo(x + rr * Math.cos(a), y + rr * Math.sin(a));
  }
  ctx.closePath();
  ctx.fillStyle = '#9b59d0';
  ctx.fill();
  ctx.strokeStyle = '#fff';
  ctx.lineWidth = 1.2;
  ctx.stroke();
}

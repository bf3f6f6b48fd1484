// The static 3D world: terrain mesh from the heightmap, extruded buildings, streets,
// bridges, forbidden zones and places draped on the ground.

import * as THREE from 'three';
import { groundAt } from './terrain.js';

const MAX_GRID = 256; // terrain samples per side drawn at most

function terrainMesh(scene) {
  const t = scene.terrain;
  const [x0, y0, x1, y1] = scene.extent;
  const geo = new THREE.BufferGeometry();
  let nx;
  let ny;
  let px;
  let py;
  if (t.nx >= 2 && t.ny >= 2) {
    const step = Math.max(1, Math.ceil(Math.max(t.nx, t.ny) / MAX_GRID));
    nx = Math.floor((t.nx - 1) / step) + 1;
    ny = Math.floor((t.ny - 1) / step) + 1;
    px = (i) => t.origin[0] + i * step * t.cell;
    py = (j) => t.origin[1] + j * step * t.cell;
  } else {
    // flat ground a little wider than the town
    const m = 0.1 * Math.max(x1 - x0, y1 - y0, 100);
    nx = ny = 2;
    px = (i) => (i ? x1 + m : x0 - m);
    py = (j) => (j ? y1 + m : y0 - m);
  }
  const pos = new Float32Array(nx * ny * 3);
  const col = new Float32Array(nx * ny * 3);
  let lo = Infinity;
  let hi = -Infinity;
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      const z = groundAt(t, px(i), py(j));
      lo = Math.min(lo, z);
      hi = Math.max(hi, z);
      pos.set([px(i), py(j), z], (j * nx + i) * 3);
    }
  }
  const c = new THREE.Color();
  for (let k = 0; k < nx * ny; k++) {
    const h = hi > lo ? (pos[k * 3 + 2] - lo) / (hi - lo) : 0.2;
    c.setHSL(0.28 - 0.2 * h, 0.35, 0.5 + 0.15 * h);
    col.set([c.r, c.g, c.b], k * 3);
  }
  const idx = [];
  for (let j = 0; j < ny - 1; j++) {
    for (let i = 0; i < nx - 1; i++) {
      const a = j * nx + i;
      idx.push(a, a + 1, a + nx + 1, a, a + nx + 1, a + nx);
    }
  }
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
  geo.setIndex(idx);
  geo.computeVertexNormals();
  return new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ vertexColors: true }));
}

function buildingsMesh(buildings) {
  const pos = [];
  for (const b of buildings) {
    let ring = b.footprint.map(([x, y]) => new THREE.Vector2(x, y));
    if (ring.length < 3) continue;
    if (THREE.ShapeUtils.isClockWise(ring)) ring = ring.reverse();
    const z0 = b.base;
    const z1 = b.base + b.height;
    for (const [a, b2, c] of THREE.ShapeUtils.triangulateShape(ring, [])) {
      pos.push(ring[a].x, ring[a].y, z1, ring[b2].x, ring[b2].y, z1, ring[c].x, ring[c].y, z1);
    }
    for (let i = 0; i < ring.length; i++) {
      const p = ring[i];
      const q = ring[(i + 1) % ring.length];
      pos.push(p.x, p.y, z0, q.x, q.y, z0, q.x, q.y, z1, p.x, p.y, z0, q.x, q.y, z1, p.x, p.y, z1);
    }
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  geo.computeVertexNormals();
  return new THREE.Mesh(geo, new THREE.MeshLambertMaterial({ color: 0xc9b8a6 }));
}

/** Polylines as one set of line segments, lifted `lift` metres above their own z. */
function lines(polys, color, lift, opacity = 1) {
  const pos = [];
  for (const p of polys) {
    for (let i = 0; i + 1 < p.length; i++) pos.push(p[i][0], p[i][1], p[i][2] + lift, p[i + 1][0], p[i + 1][1], p[i + 1][2] + lift);
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  return new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity }));
}

/** A text label that keeps its size on screen. */
export function label(text, color = '#111', height = 0.028) {
  const c = document.createElement('canvas');
  const ctx = c.getContext('2d');
  const font = 'bold 28px system-ui, sans-serif';
  ctx.font = font;
  const w = Math.ceil(ctx.measureText(text).width) + 16;
  c.width = w;
  c.height = 40;
  ctx.font = font;
  ctx.fillStyle = 'rgba(255,255,255,0.8)';
  ctx.fillRect(0, 0, w, 40);
  ctx.fillStyle = color;
  ctx.textBaseline = 'middle';
  ctx.fillText(text, 8, 21);
  const tex = new THREE.CanvasTexture(c);
  tex.colorSpace = THREE.SRGBColorSpace;
  const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: tex, sizeAttenuation: false, depthTest: false }));
  s.scale.set((height * w) / 40, height, 1);
  s.center.set(0, 0);
  s.renderOrder = 10;
  return s;
}

/** Everything static, as one group; `layers` decides what is included. */
export function buildWorld(scene, layers) {
  const g = new THREE.Group();
  const t = scene.terrain;
  const drape = (ring) => ring.map(([x, y]) => [x, y, groundAt(t, x, y)]);
  if (layers.terrain) g.add(terrainMesh(scene));
  if (layers.buildings && scene.buildings.length) g.add(buildingsMesh(scene.buildings));
  if (layers.streets && scene.streets.length) g.add(lines(scene.streets, 0xffffff, 0.6));
  if (layers.paths && scene.paths.length) g.add(lines(scene.paths, 0x8a6b42, 0.5, 0.8));
  if (layers.bridges && scene.bridges.length) g.add(lines(scene.bridges, 0x333333, 1.0));
  if (layers.forbidden && scene.forbidden.length) {
    g.add(lines(scene.forbidden.map((r) => drape([...r, r[0]])), 0xd03030, 0.8, 0.8));
  }
  if (layers.places) {
    for (const [name, p] of Object.entries(scene.places)) {
      const s = label(`★ ${name}`, '#5a2d82', 0.03);
      s.position.set(p[0], p[1], p[2] + 15);
      g.add(s);
    }
  }
  return g;
}

// The 3D view (three.js): terrain, buildings, entities at their altitude, lines of sight,
// the selected agent's path, and a camera that follows a chosen entity.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { layers } from './layers.js';
import { isAir, symbolCanvas } from './symbols.js';
import { groundAt } from './terrain.js';
import { buildWorld, label } from './world3d.js';

const SIDE_COLOR = { friendly: 0x2f86d6, hostile: 0xd63a3a, neutral: 0x2fa05a, unknown: 0xd6c02f };
const LOS_COLOR = { friendly: 0x1060c0, hostile: 0xc01010, neutral: 0x108040, unknown: 0xa09000 };

function body(kind, side, k) {
  const mat = new THREE.MeshLambertMaterial({ color: SIDE_COLOR[side] || SIDE_COLOR.unknown });
  const g = new THREE.Group();
  const add = (geo, x = 0, y = 0, z = 0) => {
    const m = new THREE.Mesh(geo, mat);
    m.position.set(x * k, y * k, z * k);
    g.add(m);
  };
  switch (kind) {
    case 'truck':
      add(new THREE.BoxGeometry(7 * k, 2.5 * k, 3 * k), 0, 0, 1.6);
      break;
    case 'car':
      add(new THREE.BoxGeometry(4.5 * k, 1.9 * k, 1.5 * k), 0, 0, 0.8);
      break;
    case 'ugv':
      add(new THREE.BoxGeometry(2.2 * k, 1.3 * k, 1.1 * k), 0, 0, 0.6);
      break;
    case 'ctol':
      add(new THREE.BoxGeometry(2.4 * k, 0.35 * k, 0.35 * k));
      add(new THREE.BoxGeometry(0.5 * k, 4.2 * k, 0.08 * k), 0.2);
      add(new THREE.BoxGeometry(0.3 * k, 1.4 * k, 0.06 * k), -1.1);
      break;
    case 'vtol':
      add(new THREE.BoxGeometry(2.5 * k, 0.8 * k, 0.9 * k));
      add(new THREE.CylinderGeometry(2.4 * k, 2.4 * k, 0.05 * k, 24).rotateX(Math.PI / 2), 0, 0, 0.6);
      break;
    default: // people
      add(new THREE.CylinderGeometry(0.35 * k, 0.35 * k, 1.4 * k, 10).rotateX(Math.PI / 2), 0, 0, 0.7);
      add(new THREE.SphereGeometry(0.28 * k, 10, 8), 0, 0, 1.65);
  }
  return g;
}

export class View3D {
  constructor(el, state) {
    this.el = el;
    this.state = state;
    this.ready = false;
    this.visible = false;
    this.follow = null;
    this.entities = new Map(); // id -> {group, key}
  }

  /** Creates the renderer on first use (pages that never open 3D need no WebGL). */
  init() {
    if (this.ready || this.failed) return this.ready;
    try {
      this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      this.failed = true;
      this.el.innerHTML = `<p class="muted" style="padding:20px">3D view unavailable: ${String(e.message || e)}</p>`;
      return false;
    }
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.el.append(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xbfd4e6);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x6b6b55, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(-1, 1.5, 2);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(45, 1, 1, 1e6);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.controls.maxPolarAngle = Math.PI * 0.49;
    this.dynamic = new THREE.Group();
    this.scene.add(this.dynamic);
    new ResizeObserver(() => this.resize()).observe(this.el);
    this.resize();
    this.ready = true;
    if (this.state.scene) this.setScene();
    const loop = () => {
      if (this.visible) {
        this.controls.update();
        this.renderer.render(this.scene, this.camera);
      }
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
    return true;
  }

  resize() {
    const w = this.el.clientWidth || 1;
    const h = this.el.clientHeight || 1;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  show(on) {
    this.visible = on;
    this.el.hidden = !on;
    if (on && this.init()) {
      this.resize();
      this.update();
    }
  }

  setScene() {
    if (!this.ready) return;
    const s = this.state.scene;
    if (this.world) this.scene.remove(this.world);
    this.world = buildWorld(s, layers);
    this.scene.add(this.world);
    const [x0, y0, x1, y1] = s.extent;
    const size = Math.max(x1 - x0, y1 - y0, 100);
    this.k = Math.min(6, Math.max(1.5, size / 400)); // entity models enlarged to stay visible
    const cx = (x0 + x1) / 2;
    const cy = (y0 + y1) / 2;
    const cz = groundAt(s.terrain, cx, cy);
    this.controls.target.set(cx, cy, cz);
    this.camera.position.set(cx - 0.15 * size, cy - 0.85 * size, cz + 0.6 * size);
    this.camera.far = size * 20;
    this.camera.updateProjectionMatrix();
    this.scene.fog = new THREE.Fog(0xbfd4e6, size * 1.5, size * 6);
    for (const { group } of this.entities.values()) this.dynamic.remove(group);
    this.entities.clear();
  }

  /** Rebuilds the static world (after a layer toggle). */
  relayer() {
    if (this.ready && this.state.scene) {
      if (this.world) this.scene.remove(this.world);
      this.world = buildWorld(this.state.scene, layers);
      this.scene.add(this.world);
    }
  }

  /** Looks at the world box [x0, y0, x1, y1] from the south, 40° down. */
  lookAtBox([x0, y0, x1, y1]) {
    if (!this.init()) return;
    const t = this.state.scene.terrain;
    const cx = (x0 + x1) / 2;
    const cy = (y0 + y1) / 2;
    const cz = groundAt(t, cx, cy);
    const d = Math.max(x1 - x0, y1 - y0, 100) * 1.1;
    this.controls.target.set(cx, cy, cz);
    this.camera.position.set(cx - 0.2 * d, cy - 0.8 * d, cz + 0.7 * d);
  }

  setFollow(id) {
    this.follow = id;
    const e = id != null ? this.state.byId.get(id) : null;
    if (!this.ready || !e) return;
    // behind and above the entity, looking along its heading
    const d = 60 * this.k;
    const h = Math.cos(e.heading);
    const v = Math.sin(e.heading);
    this.controls.target.set(e.pos[0], e.pos[1], e.pos[2]);
    this.camera.position.set(e.pos[0] - h * d, e.pos[1] - v * d, e.pos[2] + 0.6 * d);
  }

  update() {
    if (!this.ready || !this.visible || !this.state.frame) return;
    const st = this.state;
    const seen = new Set();
    for (const e of st.frame.entities) {
      seen.add(e.id);
      const key = `${e.kind}/${e.side}/${e.name}/${e.status}`;
      let ent = this.entities.get(e.id);
      if (!ent || ent.key !== key) {
        if (ent) {
          this.dynamic.remove(ent.group);
          if (ent.stalk) this.dynamic.remove(ent.stalk);
        }
        const group = new THREE.Group();
        const model = body(e.kind, e.side, this.k);
        // the map symbol, always facing the camera and the same size on screen
        const tex = new THREE.CanvasTexture(symbolCanvas(e.side, e.kind, 40, e.status));
        tex.colorSpace = THREE.SRGBColorSpace;
        const sym = new THREE.Sprite(new THREE.SpriteMaterial({ map: tex, sizeAttenuation: false, depthTest: false }));
        sym.scale.set(0.05 * 1.6, 0.05, 1);
        sym.renderOrder = 11;
        const tag = label(e.name, '#111', 0.02);
        tag.center.set(0.5, -1.4);
        group.add(model, sym, tag);
        let stalk = null;
        if (isAir(e.kind)) {
          const geo = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]);
          stalk = new THREE.Line(geo, new THREE.LineBasicMaterial({ color: 0x333333 }));
          this.dynamic.add(stalk);
        }
        ent = { group, model, sym, tag, stalk, key };
        this.entities.set(e.id, ent);
        this.dynamic.add(group);
      }
      ent.group.position.set(e.pos[0], e.pos[1], e.pos[2]);
      // passengers ride inside their vehicle
      ent.group.visible = e.status !== 'aboard';
      ent.model.rotation.z = e.heading;
      ent.tag.visible = layers.labels;
      if (ent.stalk) {
        const p = ent.stalk.geometry.attributes.position;
        p.setXYZ(0, e.pos[0], e.pos[1], e.pos[2]);
        p.setXYZ(1, e.pos[0], e.pos[1], groundAt(st.scene.terrain, e.pos[0], e.pos[1]));
        p.needsUpdate = true;
      }
    }
    for (const [id, ent] of this.entities) {
      if (!seen.has(id)) {
        this.dynamic.remove(ent.group);
        if (ent.stalk) this.dynamic.remove(ent.stalk);
        this.entities.delete(id);
      }
    }
    this.overlays();
    if (this.follow != null) {
      const e = st.byId.get(this.follow);
      if (e) {
        const t = this.controls.target;
        const d = new THREE.Vector3(e.pos[0] - t.x, e.pos[1] - t.y, e.pos[2] - t.z);
        t.add(d);
        this.camera.position.add(d);
      }
    }
  }

  /** Lines of sight and the selected agent's path, rebuilt each frame. */
  overlays() {
    if (this.lines) {
      this.dynamic.remove(this.lines);
      this.lines.geometry.dispose();
    }
    const st = this.state;
    const pos = [];
    const col = [];
    const c = new THREE.Color();
    const seg = (a, b, color) => {
      pos.push(...a, ...b);
      c.setHex(color);
      col.push(c.r, c.g, c.b, c.r, c.g, c.b);
    };
    if (layers.detections) for (const d of st.frame.detections) seg(d.from, d.to, LOS_COLOR[d.seen_as] || 0);
    const it = st.selected != null ? st.intentionOf(st.selected) : null;
    const me = st.selected != null ? st.byId.get(st.selected) : null;
    if (it && it.path.length) {
      const pts = me ? [me.pos, ...it.path] : it.path;
      for (let i = 0; i + 1 < pts.length; i++) seg([pts[i][0], pts[i][1], pts[i][2] + 1], [pts[i + 1][0], pts[i + 1][1], pts[i + 1][2] + 1], 0x7b2fb5);
    }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
    this.lines = new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ vertexColors: true }));
    this.dynamic.add(this.lines);
  }
}

// The inspector: the selected entity as the frame reports it (state, sensors, detections),
// its intention and plan (repaired against original), and its recent messages.

import { bearing, clock, esc, num, pos } from './format.js';
import { isAir, KIND_NAMES, symbolCanvas } from './symbols.js';
import { aboveGround } from './terrain.js';

const MESSAGES_SHOWN = 6;

export class Inspector {
  constructor(el, state) {
    this.el = el;
    this.state = state;
    this.shown = null;
  }

  update() {
    const st = this.state;
    const id = st.selected;
    const e = id != null ? st.byId.get(id) : null;
    if (!e) {
      if (this.shown !== 'none') {
        this.el.innerHTML = `<p class="muted">${id != null ? 'The selected entity is not in this frame.' : 'Click an entity on the map.'}</p>`;
        this.shown = 'none';
      }
      return;
    }
    this.shown = id;
    const f = st.frame;
    const name = (n) => esc(st.byId.get(n) ? st.byId.get(n).name : `#${n}`);
    const rows = [
      ['type', `${esc(KIND_NAMES[e.kind] || e.kind)} <span class="muted">(${esc(e.kind)})</span>`],
      ['side', esc(e.side)],
      ['level', esc(e.level)],
      ['status', esc(e.status)],
      ['position', pos(e.pos)],
      ...(isAir(e.kind) ? [['altitude', `${num(aboveGround(st.scene.terrain, e.pos))} m above ground`]] : []),
      ['heading', `${bearing(e.heading)} <span class="muted">(${num(e.heading)} rad from east)</span>`],
      ['speed', `${num(e.speed)} m/s`],
      ['id', String(e.id)],
    ];
    let html = `<div class="name" data-id="${e.id}"><span class="sym"></span><span id="inspected-name">${esc(e.name)}</span></div>`;
    html += `<table>${rows.map(([k, v]) => `<tr><td>${k}</td><td>${v}</td></tr>`).join('')}</table>`;

    const sens = (f.sensors || []).filter((s) => s.id === id);
    if (sens.length) {
      html += '<h3>Sensors</h3><ul>';
      for (const s of sens) {
        const fov = s.fov >= Math.PI * 2 - 1e-6 ? 'all around' : `${Math.round((s.fov * 180) / Math.PI)}° towards ${bearing(s.heading)}`;
        html += `<li>${esc(s.kind)}: ${num(s.range)} m, ${fov}</li>`;
      }
      html += '</ul>';
    }
    const sees = f.detections.filter((d) => d.observer === id);
    const seenBy = f.detections.filter((d) => d.target === id);
    if (sees.length || seenBy.length) {
      html += '<h3>Detections</h3><ul>';
      for (const d of sees) html += `<li>sees ${name(d.target)} as ${esc(d.seen_as)}</li>`;
      for (const d of seenBy) html += `<li>seen by ${name(d.observer)} as ${esc(d.seen_as)}</li>`;
      html += '</ul>';
    }

    const it = st.intentionOf(id);
    html += '<h3>Intention</h3>';
    if (!it) {
      html += '<p class="muted">states none</p>';
    } else {
      html += `<p id="intention">${esc(it.text)}</p>`;
      const list = (steps, cls) => (steps.length ? `<ol class="${cls}">${steps.map((s) => `<li>${esc(s)}</li>`).join('')}</ol>` : '<p class="muted">no steps</p>');
      if (it.original_plan && it.original_plan.length) {
        html += `<div class="plans"><div><b>repaired plan</b>${list(it.plan, 'repaired')}</div><div><b>original plan</b>${list(it.original_plan, 'original')}</div></div>`;
      } else if (it.plan.length) {
        html += `<b>plan</b>${list(it.plan, '')}`;
      }
      const extras = [];
      if (it.path.length) extras.push(`path of ${it.path.length} points (purple on the map)`);
      if (it.heat && it.heat.length) extras.push(`policy over ${it.heat.length} places (orange)`);
      if (it.belief && it.belief.length) extras.push(`belief over ${it.belief.length} places (violet)`);
      if (extras.length) html += `<p class="muted">${extras.join('; ')}</p>`;
    }

    const msgs = st.messages.filter((m) => m.from === id || m.to === id || m.to == null).slice(-MESSAGES_SHOWN).reverse();
    html += '<h3>Messages</h3>';
    if (!msgs.length) {
      html += '<p class="muted">none seen yet</p>';
    } else {
      html += '<ul>';
      for (const m of msgs) {
        const dir = m.from === id ? `→ ${m.to == null ? 'all' : name(m.to)}` : `← ${name(m.from)}`;
        html += `<li class="msg${m.delivered ? '' : ' lost'}">${clock(m.t_ns)} ${dir} ${esc(m.kind)}${m.delivered ? '' : ' (lost)'}</li>`;
      }
      html += '</ul>';
    }
    this.el.innerHTML = html;
    this.el.querySelector('.sym').append(symbolCanvas(e.side, e.kind, 22, e.status));
  }
}

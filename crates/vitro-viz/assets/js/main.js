// The page: connects to the server and keeps the map, 3D view, controls, inspector, charts
// and legend up to date. `window.vitro` exposes the state to scripts and tests.

import { Charts } from './charts.js';
import { Controls } from './controls.js';
import { clock, esc } from './format.js';
import { Inspector } from './inspector.js';
import { layerControls } from './layers.js';
import { Legend } from './legend.js';
import { Map2D } from './map2d.js';
import { Connection } from './net.js';
import { State } from './state.js';
import { View3D } from './view3d.js';

const PANEL_EVERY_MS = 250; // inspector, charts, legend and log refresh at most this often

const state = new State();
const $ = (id) => document.getElementById(id);
const map = new Map2D($('map'), state);
const view3d = new View3D($('view3d'), state);
const inspector = new Inspector($('inspector'), state);
const charts = new Charts($('charts'), state);
const legend = new Legend($('legend'), state);
const net = new Connection(
  (msg) => state.handle(msg),
  (up) => controls.onConnection(up),
);
const controls = new Controls(state, net);

let panelsDue = 0;
function panels(force = false) {
  const now = performance.now();
  if (!force && now < panelsDue) return;
  panelsDue = now + PANEL_EVERY_MS;
  inspector.update();
  charts.update();
  legend.update();
  const log = $('log');
  const items = state.log.slice(-40).reverse();
  log.innerHTML = items.map(([t, line]) => `<li><span class="muted">${clock(t)}</span> ${esc(line)}</li>`).join('');
}

function followOptions() {
  const sel = $('follow');
  const want = [...state.byId.values()].map((e) => `${e.id}:${e.name}`).join('|');
  if (sel.dataset.key === want) return;
  sel.dataset.key = want;
  const cur = sel.value;
  sel.replaceChildren(new Option('nobody', ''));
  for (const e of state.byId.values()) sel.append(new Option(e.name, String(e.id)));
  sel.value = cur;
}

state.on((kind) => {
  switch (kind) {
    case 'hello':
      controls.onHello();
      break;
    case 'scene':
      map.setScene();
      view3d.setScene();
      panels(true);
      break;
    case 'frame':
      controls.onFrame();
      map.invalidate();
      view3d.update();
      followOptions();
      panels();
      break;
    case 'status':
      controls.onStatus();
      break;
    case 'select':
      map.invalidate();
      view3d.update();
      panels(true);
      break;
    case 'history':
      panels(true);
      break;
    default:
  }
});

layerControls($('layers'), () => {
  map.invalidate(true);
  view3d.relayer();
  view3d.update();
  panels(true);
});

function showTab(three) {
  $('tab2d').classList.toggle('on', !three);
  $('tab3d').classList.toggle('on', three);
  $('map').hidden = three;
  map.visible = !three;
  $('hint').textContent = three ? 'drag to orbit · right-drag to pan · wheel to zoom' : 'drag to pan · wheel to zoom · click an entity to inspect it';
  view3d.show(three);
  if (!three) map.invalidate(true);
}
$('tab2d').addEventListener('click', () => showTab(false));
$('tab3d').addEventListener('click', () => showTab(true));
$('follow').addEventListener('change', () => {
  const v = $('follow').value;
  const id = v === '' ? null : Number(v);
  map.follow = id;
  view3d.setFollow(id);
  if (id != null) state.select(id);
  map.invalidate(true);
});

window.vitro = {
  state,
  map,
  view3d,
  /** Page coordinates of an entity's symbol on the 2D map. */
  screenPos: (id) => map.screenPos(id),
  /** Switches to the 3D (true) or the 2D view. */
  show3d: (on) => showTab(on),
  send: (cmd) => net.send(cmd),
};

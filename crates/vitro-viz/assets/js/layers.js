// Layer toggles: which parts of the map (2D and 3D) are drawn.

export const LAYERS = [
  ['terrain', 'terrain', true],
  ['streets', 'streets', true],
  ['paths', 'footpaths', true],
  ['buildings', 'buildings', true],
  ['bridges', 'bridges', true],
  ['forbidden', 'forbidden zones', true],
  ['places', 'places', true],
  ['labels', 'names', true],
  ['trails', 'trails', true],
  ['sensors', 'sensor footprints', true],
  ['detections', 'lines of sight', true],
  ['messages', 'messages', false],
  ['intentions', 'all plans', false],
  ['heat', 'patrol heat map', true],
  ['belief', 'pursuer belief', true],
];

/** The current toggles: key -> boolean. */
export const layers = Object.fromEntries(LAYERS.map(([k, , on]) => [k, on]));

/** Builds the checkboxes into `el`; onChange() after each toggle. */
export function layerControls(el, onChange) {
  el.textContent = '';
  for (const [key, label] of LAYERS) {
    const l = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = layers[key];
    box.dataset.layer = key;
    box.addEventListener('change', () => {
      layers[key] = box.checked;
      onChange(key);
    });
    l.append(box, label);
    el.append(l);
  }
}

// The page's controls around the 3-D view: layer switches with their counts,
// the class legend, the info panel of what was clicked, and a short help line.
// Plain DOM, so the page needs nothing beyond the one bundled script.

const STYLE = `
html, body { margin: 0; height: 100%; overflow: hidden; background: #20242c; font: 13px/1.4 system-ui, sans-serif; }
#sarmap-view { position: fixed; inset: 0; }
.sarmap-panel { position: fixed; background: rgba(250, 250, 250, 0.92); color: #222; border-radius: 6px;
  padding: 8px 10px; box-shadow: 0 1px 4px rgba(0, 0, 0, 0.4); }
#sarmap-layers { top: 10px; left: 10px; max-width: 320px; }
#sarmap-legend { top: 10px; right: 10px; }
#sarmap-info { bottom: 10px; left: 10px; min-width: 200px; white-space: pre; font-family: ui-monospace, monospace; }
#sarmap-info[hidden] { display: none; }
#sarmap-help { bottom: 10px; right: 10px; color: #555; }
.sarmap-panel h1 { font-size: 14px; margin: 0 0 6px; }
.sarmap-panel label { display: block; cursor: pointer; }
.sarmap-count { color: #666; }
.sarmap-swatch { display: inline-block; width: 12px; height: 12px; margin-right: 6px; vertical-align: -2px;
  border: 1px solid #444; }
.sarmap-note { color: #a33; margin-top: 6px; }
`;

function element(tag, attributes = {}, text = '') {
  const e = document.createElement(tag);
  Object.assign(e, attributes);
  if (text) e.textContent = text;
  return e;
}

export function addStyle() {
  document.head.appendChild(element('style', {}, STYLE));
}

function countText(layer) {
  const n = (v) => v.toLocaleString('en');
  return layer.total !== layer.count ? `${n(layer.count)} of ${n(layer.total)}` : n(layer.count);
}

// One checkbox per layer; onToggle(name, visible) is called on a change.
export function layerPanel(run, layers, names, onToggle) {
  const panel = element('div', { id: 'sarmap-layers', className: 'sarmap-panel' });
  panel.appendChild(element('h1', {}, `sarmap: ${run}`));
  for (const [name, layer] of Object.entries(layers)) {
    const box = element('input', { type: 'checkbox', checked: layer.object.visible, id: `sarmap-layer-${name}` });
    box.addEventListener('change', () => onToggle(name, box.checked));
    const label = element('label');
    label.append(box, ` ${names[name]} `, element('span', { className: 'sarmap-count' }, `(${countText(layer)})`));
    panel.appendChild(label);
  }
  if (Object.keys(layers).length === 0) panel.appendChild(element('div', { className: 'sarmap-note' }, 'this run holds nothing to draw'));
  document.body.appendChild(panel);
  return panel;
}

// The classes with their colours and how many occupied voxels each holds;
// onToggle(classId, visible) when a class is ticked or unticked.
export function legend(classes, voxelLabels, onToggle) {
  const counts = new Array(classes.length).fill(0);
  if (voxelLabels) for (const label of voxelLabels) counts[label] += 1;
  const panel = element('div', { id: 'sarmap-legend', className: 'sarmap-panel' });
  panel.appendChild(element('h1', {}, 'classes'));
  for (const c of classes) {
    const row = element('label');
    const box = element('input', { type: 'checkbox', checked: true, id: `sarmap-class-${c.id}` });
    box.addEventListener('change', () => onToggle(c.id, box.checked));
    const swatch = element('span', { className: 'sarmap-swatch' });
    swatch.style.background = `rgb(${c.color.join(',')})`;
    row.append(box, swatch, c.label);
    if (voxelLabels) row.append(element('span', { className: 'sarmap-count' }, ` ${counts[c.id].toLocaleString('en')}`));
    panel.appendChild(row);
  }
  document.body.appendChild(panel);
}

export function helpLine() {
  document.body.appendChild(element('div', { id: 'sarmap-help', className: 'sarmap-panel' },
    'drag: orbit · right drag: pan · wheel: zoom · click: inspect'));
}

function formatted(key, value) {
  // Rounding can leave "-0.000", which reads as a sign that is not there.
  if (Array.isArray(value)) return value.map((v) => (Math.abs(v) < 5e-4 ? 0 : v).toFixed(3)).join(', ');
  if (typeof value === 'number' && !Number.isInteger(value)) return value.toFixed(key === 'probability' ? 3 : 2);
  return String(value);
}

// Shows one picked item's fields ({kind, id, class, ...}); null hides the panel.
export function infoPanel() {
  const panel = element('div', { id: 'sarmap-info', className: 'sarmap-panel', hidden: true });
  document.body.appendChild(panel);
  return (item) => {
    panel.hidden = !item;
    if (!item) return;
    const lines = [`${item.kind}${item.id !== undefined ? ` ${item.id}` : ''}`];
    for (const [key, value] of Object.entries(item)) {
      if (key === 'kind' || key === 'id' || value === null || value === undefined) continue;
      lines.push(`${key.replace('_', ' ')}: ${formatted(key, value)}`);
    }
    panel.textContent = lines.join('\n');
  };
}

// The viewer `sarmap view` inlines into view.html: reads the run's layers
// from the page's JSON, draws them with three.js (orbit, pan, zoom; click to
// inspect), and exposes window.sarmapView for tests and scripts:
//   ready, error, webgl2, layers: {name: {count, total, visible}},
//   setVisible(name, on), toggle(name), showOnly(name), showAll(), hideAll(),
//   setClassVisible(classId, on), hiddenClasses,
//   describe(name, index), screenPoint([x, y, z]), screenPointOf(name, index),
//   pickAt(clientX, clientY), selected.
// It draws only on a change (no animation loop), so an idle page costs nothing.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { buildLayers, LAYER_NAMES } from './layers.js';
import { addStyle, helpLine, infoPanel, layerPanel, legend } from './panel.js';

const api = { ready: false, error: null, webgl2: false, layers: {}, selected: null };
window.sarmapView = api;

function start() {
  addStyle();
  const data = JSON.parse(document.getElementById('sarmap-data').textContent);
  const container = document.createElement('div');
  container.id = 'sarmap-view';
  document.body.appendChild(container);

  const renderer = new THREE.WebGLRenderer({ antialias: true });
  api.webgl2 = typeof WebGL2RenderingContext !== 'undefined' && renderer.getContext() instanceof WebGL2RenderingContext;
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.setClearColor(0x20242c);
  container.appendChild(renderer.domElement);

  const scene = new THREE.Scene();
  scene.add(new THREE.AmbientLight(0xffffff, 1.2));
  const sun = new THREE.DirectionalLight(0xffffff, 1.8);
  sun.position.set(-0.4, -0.6, 1);
  scene.add(sun);

  const bounds = new THREE.Box3();
  const layers = buildLayers(data, bounds);
  for (const layer of Object.values(layers)) scene.add(layer.object);
  if (bounds.isEmpty()) bounds.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));

  // Coordinates are z up; the camera starts above one corner, looking at the middle.
  const center = bounds.getCenter(new THREE.Vector3());
  const extent = Math.max(bounds.getSize(new THREE.Vector3()).length(), 1);
  const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, extent / 2000, extent * 20);
  camera.up.set(0, 0, 1);
  camera.position.copy(center).add(new THREE.Vector3(-0.45, -0.85, 0.75).normalize().multiplyScalar(extent * 1.05));
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(center);
  controls.update();

  const render = () => renderer.render(scene, camera);
  let queued = false;
  const renderSoon = () => {
    if (queued) return;
    queued = true;
    requestAnimationFrame(() => {
      queued = false;
      render();
    });
  };
  controls.addEventListener('change', renderSoon);
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
    render();
  });

  const show = infoPanel();
  const checkbox = (name) => document.getElementById(`sarmap-layer-${name}`);
  for (const [name, layer] of Object.entries(layers)) {
    api.layers[name] = { count: layer.count, total: layer.total, visible: true };
  }
  // Each call draws once, after all its changes: a software renderer pays per frame.
  const setLayer = (name, on) => {
    const layer = layers[name];
    if (!layer) throw new Error(`no layer '${name}' in this run`);
    layer.object.visible = on;
    api.layers[name].visible = on;
    checkbox(name).checked = on;
  };
  api.setVisible = (name, on) => {
    setLayer(name, on);
    render();
  };
  api.toggle = (name) => api.setVisible(name, !api.layers[name].visible);
  api.showOnly = (name) => {
    Object.keys(layers).forEach((n) => setLayer(n, n === name));
    render();
  };
  api.showAll = () => {
    Object.keys(layers).forEach((n) => setLayer(n, true));
    render();
  };
  api.hideAll = () => api.showOnly(null);
  // Classes hidden in the legend, across the point and voxel layers.
  api.hiddenClasses = [];
  api.setClassVisible = (classId, on) => {
    for (const layer of Object.values(layers)) {
      for (const child of layer.object.children) {
        if (child.userData.classId === classId) child.visible = on;
      }
    }
    api.hiddenClasses = api.hiddenClasses.filter((c) => c !== classId).concat(on ? [] : [classId]);
    const box = document.getElementById(`sarmap-class-${classId}`);
    if (box) box.checked = on;
    render();
  };
  api.describe = (name, index) => layers[name].describe(index);
  api.screenPoint = (p) => {
    const v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
    const rect = renderer.domElement.getBoundingClientRect();
    return { x: rect.left + (v.x + 1) / 2 * rect.width, y: rect.top + (1 - v.y) / 2 * rect.height };
  };
  // Where on the screen an item of a layer is drawn (to click it).
  api.screenPointOf = (name, index) => {
    const layer = layers[name];
    return api.screenPoint(layer.drawnAt ? layer.drawnAt(index) : layer.describe(index).position);
  };

  // The picked item's place, drawn over everything so it shows inside a wall of cubes too.
  const marker = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(1, 1, 1)),
    new THREE.LineBasicMaterial({ color: 0xffffff, depthTest: false }));
  marker.renderOrder = 1;
  marker.visible = false;
  marker.scale.setScalar(Math.max(0.08, 1.5 * ((data.layers.voxels && data.layers.voxels.size) || 0.05)));
  scene.add(marker);

  // The nearest visible voxel, segment or node under the pointer.
  const raycaster = new THREE.Raycaster();
  api.pickAt = (x, y) => {
    const rect = renderer.domElement.getBoundingClientRect();
    raycaster.setFromCamera(new THREE.Vector2((x - rect.left) / rect.width * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1),
      camera);
    let best = null;
    for (const layer of Object.values(layers)) {
      if (!layer.pickable || !layer.object.visible) continue;
      // The raycaster does not skip hidden objects: a class hidden in the legend must not be picked.
      const hit = raycaster.intersectObject(layer.pickable, true).find((h) => h.object.visible);
      if (hit && (!best || hit.distance < best.hit.distance)) best = { hit, layer };
    }
    const index = best ? best.layer.indexOfHit(best.hit) : -1;
    api.selected = best ? best.layer.describe(index) : null;
    show(api.selected);
    marker.visible = !!api.selected;
    if (api.selected) marker.position.set(...(best.layer.drawnAt ? best.layer.drawnAt(index) : api.selected.position));
    render();
    return api.selected;
  };
  // A click, not the end of a drag, inspects.
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) api.pickAt(e.clientX, e.clientY);
    down = null;
  });

  layerPanel(data.run, layers, LAYER_NAMES, (name, on) => api.setVisible(name, on));
  legend(data.classes, layers.voxels ? layers.voxels.labels : layers.points ? layers.points.labels : null,
    (classId, on) => api.setClassVisible(classId, on));
  helpLine();
  render();
  api.ready = true;
}

try {
  start();
} catch (e) {
  api.error = String(e && e.message ? e.message : e);
  const message = document.createElement('pre');
  message.textContent = `sarmap view could not start: ${api.error}`;
  message.style.color = '#f88';
  document.body.appendChild(message);
}

// The three.js objects of each layer a run has, built from the page's data
// (tools/sarmap/view_data.cpp gives its shape). Each layer is
// {object, count, total, describe(index), pickable, indexOfHit(hit),
// drawnAt(index) when an item is drawn away from its position}; points and
// voxels are a group with one child per class (userData.classId); many
// items share one draw call (points, instanced cubes and spheres, one
// geometry for all rectangles), so large maps stay smooth.
import * as THREE from 'three';
import { float32s, uint8s, uint32s } from './decode.js';

// Class colours as three.js colours (the page's table comes from
// engine/core/classes.hpp, so the viewer and the files agree).
export function palette(classes) {
  return classes.map((c) => new THREE.Color().setRGB(c.color[0] / 255, c.color[1] / 255, c.color[2] / 255,
    THREE.SRGBColorSpace));
}

function className(classes, id) {
  return classes[id] ? classes[id].label : `class ${id}`;
}

function xyz(v) {
  return `${v[0].toFixed(3)}, ${v[1].toFixed(3)}, ${v[2].toFixed(3)}`;
}

function colorsByLabel(labels, colors) {
  const out = new Float32Array(labels.length * 3);
  for (let i = 0; i < labels.length; ++i) {
    const c = colors[labels[i]] || colors[0];
    out[3 * i] = c.r;
    out[3 * i + 1] = c.g;
    out[3 * i + 2] = c.b;
  }
  return out;
}

function expandBy(bounds, positions) {
  const p = new THREE.Vector3();
  for (let i = 0; i + 2 < positions.length; i += 3) bounds.expandByPoint(p.set(positions[i], positions[i + 1], positions[i + 2]));
}

function pointCloud(positions, colors, size, opacity) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  const material = new THREE.PointsMaterial({ size, sizeAttenuation: true });
  if (colors.isColor) {
    material.color = colors;
  } else {
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    material.vertexColors = true;
  }
  if (opacity < 1) Object.assign(material, { transparent: true, opacity, depthWrite: false });
  return new THREE.Points(geometry, material);
}

// Item indices grouped by class, so each class is an object of its own that
// the legend can hide without rebuilding anything.
function byClass(labels, classCount) {
  const classOf = (label) => (label < classCount ? label : 0);  // an id past the table is unknown
  const counts = new Array(classCount).fill(0);
  for (const label of labels) counts[classOf(label)] += 1;
  const groups = counts.map((n) => new Uint32Array(n));
  const filled = new Array(classCount).fill(0);
  labels.forEach((label, i) => {
    const c = classOf(label);
    groups[c][filled[c]++] = i;
  });
  return groups;
}

function classGroup(labels, ctx, build) {
  const group = new THREE.Group();
  byClass(labels, ctx.classes.length).forEach((indices, classId) => {
    if (indices.length === 0) return;
    const object = build(indices, ctx.colors[classId]);
    object.userData = { classId, indices };
    group.add(object);
  });
  return group;
}

function semanticPoints(layer, ctx) {
  const positions = float32s(layer.positions);
  const labels = uint8s(layer.labels);
  expandBy(ctx.bounds, positions);
  const object = classGroup(labels, ctx, (indices, color) => {
    const own = new Float32Array(indices.length * 3);
    indices.forEach((i, k) => own.set(positions.subarray(3 * i, 3 * i + 3), 3 * k));
    return pointCloud(own, color, ctx.voxelSize * 0.9, 1);
  });
  return {
    object,
    labels,
    describe: (i) => ({ kind: 'point', id: i, class: className(ctx.classes, labels[i]),
      position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]] }),
  };
}

function occupiedVoxels(layer, ctx) {
  const positions = float32s(layer.positions);
  const labels = uint8s(layer.labels);
  const ids = uint32s(layer.ids);
  const probabilities = layer.probabilities ? float32s(layer.probabilities) : null;
  expandBy(ctx.bounds, positions);
  const cube = new THREE.BoxGeometry(layer.size, layer.size, layer.size);
  const m = new THREE.Matrix4();
  const object = classGroup(labels, ctx, (indices, color) => {
    const mesh = new THREE.InstancedMesh(cube, new THREE.MeshLambertMaterial({ color }), indices.length);
    indices.forEach((i, k) => mesh.setMatrixAt(k, m.makeTranslation(positions[3 * i], positions[3 * i + 1],
      positions[3 * i + 2])));
    mesh.computeBoundingSphere();
    return mesh;
  });
  return {
    object,
    labels,
    pickable: object,
    indexOfHit: (hit) => hit.object.userData.indices[hit.instanceId],
    describe: (i) => ({ kind: 'voxel', id: ids[i], class: className(ctx.classes, labels[i]),
      probability: probabilities ? probabilities[i] : null,
      position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]] }),
  };
}

function freeVoxels(layer, ctx) {
  const positions = float32s(layer.positions);
  expandBy(ctx.bounds, positions);
  const color = new THREE.Color(0x9cc8f0);
  return {
    object: pointCloud(positions, color, layer.size * Math.max(1, layer.stride) * 0.6, 0.18),
    describe: (i) => ({ kind: 'free voxel', id: i,
      position: [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]] }),
  };
}

// Each segment's rectangle is two triangles of one geometry, so a hit's face
// index halved is the segment.
function segmentRectangles(layer, ctx) {
  const n = layer.items.length;
  const fill = new Float32Array(n * 18);
  const fillColors = new Float32Array(n * 18);
  const outline = new Float32Array(n * 24);
  const corner = (s, u, v) => [0, 1, 2].map((k) => s.center[k] + u * s.half_extents[0] * s.axes[0][k] +
    v * s.half_extents[1] * s.axes[1][k]);
  layer.items.forEach((s, i) => {
    const c = [corner(s, -1, -1), corner(s, 1, -1), corner(s, 1, 1), corner(s, -1, 1)];
    [c[0], c[1], c[2], c[0], c[2], c[3]].forEach((p, k) => fill.set(p, 18 * i + 3 * k));
    [c[0], c[1], c[1], c[2], c[2], c[3], c[3], c[0]].forEach((p, k) => outline.set(p, 24 * i + 3 * k));
    const color = ctx.colors[s.class_id] || ctx.colors[0];
    for (let k = 0; k < 6; ++k) fillColors.set([color.r, color.g, color.b], 18 * i + 3 * k);
  });
  expandBy(ctx.bounds, outline);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(fill, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(fillColors, 3));
  const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ vertexColors: true, transparent: true,
    opacity: 0.55, side: THREE.DoubleSide, depthWrite: false }));
  const edges = new THREE.BufferGeometry();
  edges.setAttribute('position', new THREE.BufferAttribute(outline, 3));
  edges.setAttribute('color', new THREE.BufferAttribute(new Float32Array(outline.length).map((_, k) =>
    fillColors[18 * Math.floor(k / 24) + (k % 3)]), 3));
  const group = new THREE.Group();
  group.add(mesh, new THREE.LineSegments(edges, new THREE.LineBasicMaterial({ vertexColors: true })));
  return {
    object: group,
    pickable: mesh,
    indexOfHit: (hit) => Math.floor(hit.faceIndex / 2),
    describe: (i) => {
      const s = layer.items[i];
      return { kind: 'segment', id: s.id, class: className(ctx.classes, s.class_id), area_m2: s.area_m2,
        slope_deg: s.slope_deg, inliers: s.inliers, position: s.center };
    },
  };
}

function graphNodes(layer, ctx) {
  const radius = Math.max(0.04, ctx.voxelSize * 1.2);
  const mesh = new THREE.InstancedMesh(new THREE.SphereGeometry(radius, 16, 10), new THREE.MeshLambertMaterial(),
    layer.items.length);
  const m = new THREE.Matrix4();
  layer.items.forEach((node, i) => {
    mesh.setMatrixAt(i, m.makeTranslation(node.pos[0], node.pos[1], node.pos[2] + radius));
    mesh.setColorAt(i, ctx.colors[node.class_id] || ctx.colors[0]);
    ctx.bounds.expandByPoint(new THREE.Vector3(...node.pos));
  });
  mesh.computeBoundingSphere();
  return {
    object: mesh,
    pickable: mesh,
    indexOfHit: (hit) => hit.instanceId,
    describe: (i) => {
      const node = layer.items[i];
      return { kind: 'node', id: node.id, class: className(ctx.classes, node.class_id), node_kind: node.kind,
        segment: node.segment, position: node.pos };
    },
    // Where the sphere is drawn: resting on the node's ground point.
    drawnAt: (i) => [layer.items[i].pos[0], layer.items[i].pos[1], layer.items[i].pos[2] + radius],
  };
}

// Spanning-tree edges bright, the rest of the roadmap dim.
function graphEdges(layer, nodes, ctx) {
  const at = new Map(nodes.items.map((n) => [n.id, n.pos]));
  const lift = Math.max(0.04, ctx.voxelSize * 1.2);
  const positions = [];
  const colors = [];
  for (const [a, b, inTree] of layer.pairs) {
    if (!at.has(a) || !at.has(b)) continue;
    for (const p of [at.get(a), at.get(b)]) positions.push(p[0], p[1], p[2] + lift);
    const shade = inTree ? 1.0 : 0.45;
    colors.push(shade, shade, shade, shade, shade, shade);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(positions), 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(colors), 3));
  return {
    object: new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true })),
    describe: (i) => ({ kind: 'edge', source: layer.pairs[i][0], target: layer.pairs[i][1], in_tree: !!layer.pairs[i][2] }),
  };
}

// A tube, since WebGL draws lines one pixel wide whatever width is asked.
function plannedPath(layer, ctx) {
  const points = layer.points.map((p) => new THREE.Vector3(p[0], p[1], p[2] + 0.05));
  points.forEach((p) => ctx.bounds.expandByPoint(p));
  const material = new THREE.MeshBasicMaterial({ color: 0x30ff60 });
  let geometry;
  if (points.length >= 2) {
    const curve = new THREE.CurvePath();
    for (let i = 1; i < points.length; ++i) curve.add(new THREE.LineCurve3(points[i - 1], points[i]));
    geometry = new THREE.TubeGeometry(curve, Math.max(8, points.length * 4), 0.03, 8, false);
  } else {
    geometry = new THREE.SphereGeometry(0.06).translate(points[0].x, points[0].y, points[0].z);
  }
  return {
    object: new THREE.Mesh(geometry, material),
    describe: () => ({ kind: 'path', length: layer.length, graph: layer.graph, algorithm: layer.algorithm }),
  };
}

function sensorTrajectory(layer, ctx) {
  const positions = new Float32Array(layer.points.flat());
  expandBy(ctx.bounds, positions);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  const color = new THREE.Color(0xff8c1a);
  const group = new THREE.Group();
  group.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color })),
    new THREE.Points(geometry, new THREE.PointsMaterial({ color, size: 6, sizeAttenuation: false })));
  return {
    object: group,
    describe: (i) => ({ kind: 'pose', id: i, position: layer.points[i] }),
  };
}

// Display names and build order (later layers draw over earlier ones).
export const LAYER_NAMES = {
  points: 'semantic points',
  voxels: 'occupied voxels',
  free: 'free voxels',
  segments: 'segments',
  nodes: 'graph nodes',
  edges: 'graph edges',
  path: 'planned path',
  trajectory: 'sensor trajectory',
};

// Builds every layer the data holds; `bounds` grows to hold them all.
export function buildLayers(data, bounds) {
  const classes = data.classes;
  const ctx = { classes, colors: palette(classes), bounds,
    voxelSize: (data.layers.voxels && data.layers.voxels.size) || (data.layers.free && data.layers.free.size) || 0.05 };
  const builders = {
    points: (l) => semanticPoints(l, ctx),
    voxels: (l) => occupiedVoxels(l, ctx),
    free: (l) => freeVoxels(l, ctx),
    segments: (l) => segmentRectangles(l, ctx),
    nodes: (l) => graphNodes(l, ctx),
    edges: (l) => graphEdges(l, data.layers.nodes || { items: [] }, ctx),
    path: (l) => plannedPath(l, ctx),
    trajectory: (l) => sensorTrajectory(l, ctx),
  };
  const layers = {};
  for (const name of Object.keys(LAYER_NAMES)) {
    const source = data.layers[name];
    if (!source || !source.count) continue;
    const layer = builders[name](source);
    layer.name = name;
    layer.count = source.count;
    layer.total = source.total !== undefined ? source.total : source.count;
    layers[name] = layer;
  }
  return layers;
}

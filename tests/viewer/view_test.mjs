// `sarmap view` in a real browser: makes a small run (a simulated room with a
// doorway, a planned path), writes its view.html, opens it from disk in
// Debian's Chromium (headless, software WebGL) through playwright-core, and
// checks that the page has a WebGL2 context, that every layer the run has
// reports the counts of the run's own files and draws pixels with only that
// layer shown, that the layer and class switches work, and that clicking a
// voxel, a segment or a node fills the info panel (a voxel's as voxels.ply
// holds it).
// Screenshots go to WORK/screenshots/. Exit 77 (CTest's skip) when the
// browser or web/node_modules is missing.
//
// node tests/viewer/view_test.mjs --sarmap BIN --arena ARENA.json --work DIR
//   [--chromium /usr/bin/chromium] [--node-modules web/node_modules]
import { createRequire } from 'node:module';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';
import { decodePng } from './png.mjs';

const SKIP = 77;
const here = path.dirname(fileURLToPath(import.meta.url));

function options() {
  const o = {
    chromium: '/usr/bin/chromium',
    'node-modules': path.join(here, '..', '..', 'web', 'node_modules'),
  };
  const argv = process.argv.slice(2);
  for (let i = 0; i + 1 < argv.length; i += 2) o[argv[i].replace(/^--/, '')] = argv[i + 1];
  for (const key of ['sarmap', 'arena', 'work']) {
    if (!o[key]) throw new Error(`--${key} is required`);
  }
  return o;
}

let failures = 0;
let checks = 0;
function check(ok, what) {
  checks += 1;
  if (!ok) {
    failures += 1;
    console.error(`FAIL: ${what}`);
  }
}

function sarmap(o, ...args) {
  return execFileSync(o.sarmap, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
}

// The vertex element of a binary little-endian PLY: count and one accessor per property.
function readPly(file) {
  const bytes = fs.readFileSync(file);
  const end = bytes.indexOf('end_header\n') + 'end_header\n'.length;
  const header = bytes.subarray(0, end).toString('latin1').split('\n');
  const sizes = { float: 4, uchar: 1, int: 4, uint: 4, double: 8 };
  let count = 0;
  const fields = {};
  let stride = 0;
  for (const line of header) {
    const words = line.trim().split(/\s+/);
    if (words[0] === 'element' && words[1] === 'vertex') count = Number(words[2]);
    if (words[0] === 'property') {
      fields[words[2]] = { offset: stride, type: words[1] };
      stride += sizes[words[1]];
    }
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset + end);
  const get = (i, name) => {
    const f = fields[name];
    const at = i * stride + f.offset;
    return f.type === 'float' ? view.getFloat32(at, true) : view.getUint8(at);
  };
  return { count, get };
}

function nonBackgroundPixels(png, background) {
  const { width, height, channels, pixels } = decodePng(png);
  let n = 0;
  for (let i = 0; i < width * height; ++i) {
    const p = i * channels;
    if (Math.abs(pixels[p] - background[0]) > 12 || Math.abs(pixels[p + 1] - background[1]) > 12 ||
        Math.abs(pixels[p + 2] - background[2]) > 12) n += 1;
  }
  return n;
}

// A screenshot of the 3-D view alone: the panels are hidden while it is taken.
async function viewShot(page, file) {
  const bare = await page.addStyleTag({ content: '.sarmap-panel { visibility: hidden !important; }' });
  const png = await page.screenshot(file ? { path: file } : {});
  await bare.evaluate((e) => e.remove());
  return png;
}

async function main() {
  const o = options();
  if (!fs.existsSync(o.chromium)) {
    console.log(`SKIP: ${o.chromium} not found (tools/install-deps.sh installs Debian's chromium)`);
    return SKIP;
  }
  if (!fs.existsSync(path.join(o['node-modules'], 'playwright-core'))) {
    console.log(`SKIP: ${o['node-modules']}/playwright-core not found (tools/install-deps.sh runs npm ci in web/)`);
    return SKIP;
  }
  const { chromium } = createRequire(path.join(o['node-modules'], 'x.js'))('playwright-core');

  // A small run with every layer: 48 frames of a 4 x 3 m room, labels as classes.
  const started = Date.now();
  fs.rmSync(o.work, { recursive: true, force: true });
  fs.mkdirSync(path.join(o.work, 'screenshots'), { recursive: true });
  const sequence = path.join(o.work, 'sequence');
  const run = path.join(o.work, 'run');
  sarmap(o, 'simulate', o.arena, '--out', sequence, '--quiet');
  sarmap(o, 'run', sequence, '--out', run, '--classifier', 'labels', '--quiet');
  sarmap(o, 'plan', run, '--from', '0.6,0.6,0', '--to', '3.4,2.4,0', '--graph', 'roadmap', '--out',
    path.join(run, 'path.json'), '--quiet');
  sarmap(o, 'view', run, '--quiet');
  const page_file = path.join(run, 'view.html');
  check(fs.existsSync(page_file), 'sarmap view wrote view.html');

  // What the page must report, from the run's own files.
  const voxels = readPly(path.join(run, 'voxels.ply'));
  const json = (name) => JSON.parse(fs.readFileSync(path.join(run, name), 'utf8'));
  const graph = json('graph.json');
  const expected = {
    points: readPly(path.join(run, 'semantic_points.ply')).count,
    voxels: voxels.count,
    segments: json('segments.json').segments.length,
    nodes: graph.nodes.length,
    edges: graph.links.length,
    path: json('path.json').points.length,
    trajectory: JSON.parse(fs.readFileSync(path.join(sequence, 'sequence.json'), 'utf8')).frames.length,
  };

  const browser = await chromium.launch({
    executablePath: o.chromium,
    headless: true,
    args: ['--headless', '--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 960, height: 640 } });
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    await page.goto(pathToFileURL(page_file).href);
    await page.waitForFunction(() => window.sarmapView && (window.sarmapView.ready || window.sarmapView.error),
      null, { timeout: 20000 });
    const state = await page.evaluate(() => ({ error: window.sarmapView.error, webgl2: window.sarmapView.webgl2,
      layers: window.sarmapView.layers }));
    check(!state.error, `the page started (${state.error})`);
    check(state.webgl2, 'the renderer has a WebGL2 context');
    check(errors.length === 0, `no errors in the page: ${errors.join('; ')}`);

    const names = ['points', 'voxels', 'free', 'segments', 'nodes', 'edges', 'path', 'trajectory'];
    check(JSON.stringify(Object.keys(state.layers).sort()) === JSON.stringify([...names].sort()),
      `the layers are ${names.join(', ')}: got ${Object.keys(state.layers).join(', ')}`);
    for (const [name, count] of Object.entries(expected)) {
      const layer = state.layers[name] || {};
      check(layer.total === count && layer.count === count, `${name}: the page reports ${layer.count} of ${layer.total}, the run holds ${count}`);
    }
    check(state.layers.free && state.layers.free.count > 0, 'free voxels are drawn');

    // Each layer alone on the background.
    const background = [0x20, 0x24, 0x2c];
    const shots = path.join(o.work, 'screenshots');
    await page.evaluate(() => window.sarmapView.hideAll());
    const empty = await viewShot(page, path.join(shots, 'empty.png'));
    check(nonBackgroundPixels(empty, background) === 0, 'with every layer hidden the view is background only');
    const drawn = {};
    for (const name of names) {
      await page.evaluate((n) => window.sarmapView.showOnly(n), name);
      drawn[name] = nonBackgroundPixels(await viewShot(page, path.join(shots, `${name}.png`)), background);
      check(drawn[name] > 50, `${name} alone draws pixels (${drawn[name]})`);
    }
    await page.evaluate(() => window.sarmapView.showAll());
    await page.screenshot({ path: path.join(shots, 'all.png') });

    // The layer switches: unticking hides the layer, ticking shows it again.
    await page.click('#sarmap-layer-voxels');
    check(!(await page.evaluate(() => window.sarmapView.layers.voxels.visible)), 'unticking voxels hides them');
    await page.click('#sarmap-layer-voxels');
    check(await page.evaluate(() => window.sarmapView.layers.voxels.visible), 'ticking voxels shows them');

    // The legend's class switch: walls unticked leave fewer voxel pixels, ticked bring them back.
    await page.evaluate(() => window.sarmapView.showOnly('voxels'));
    const withWalls = nonBackgroundPixels(await viewShot(page), background);
    await page.click('#sarmap-class-2');
    check(JSON.stringify(await page.evaluate(() => window.sarmapView.hiddenClasses)) === '[2]', 'unticking wall hides class 2');
    const noWalls = nonBackgroundPixels(await viewShot(page, path.join(shots, 'voxels_without_walls.png')), background);
    check(noWalls > 50 && noWalls < withWalls, `voxels without walls draw fewer pixels (${noWalls} < ${withWalls})`);
    await page.click('#sarmap-class-2');
    check((await page.evaluate(() => window.sarmapView.hiddenClasses)).length === 0, 'ticking wall shows it again');

    // Click the highest voxel (nothing stands above it) and read the info panel.
    await page.evaluate(() => window.sarmapView.showOnly('voxels'));
    const target = await page.evaluate(() => {
      const v = window.sarmapView;
      let best = v.describe('voxels', 0);
      for (let i = 1; i < v.layers.voxels.count; ++i) {
        const d = v.describe('voxels', i);
        if (d.position[2] > best.position[2]) best = d;
      }
      return v.screenPoint(best.position);
    });
    await page.mouse.click(target.x, target.y);
    const info = await page.textContent('#sarmap-info');
    const shown = /^voxel (\d+)\nclass: (.+)\nprobability: ([0-9.]+)/.exec(info || '');
    check(shown !== null, `clicking a voxel shows its id, class and probability: '${info}'`);
    if (shown) {
      const id = Number(shown[1]);
      const classes = ['unknown', 'terrain', 'wall', 'inclined ramp', 'flat ramp', 'other'];
      check(shown[2] === classes[voxels.get(id, 'label')], `voxel ${id}'s class is voxels.ply's (${shown[2]})`);
      check(Math.abs(Number(shown[3]) - voxels.get(id, 'scalar_probability')) < 1e-3,
        `voxel ${id}'s probability is voxels.ply's (${shown[3]})`);
    }
    await page.screenshot({ path: path.join(shots, 'voxel_clicked.png') });

    // A segment (its rectangle's centre) and a graph node, each shown alone.
    for (const [name, pattern] of [['segments', /^segment \d+\nclass: /], ['nodes', /^node \d+\nclass: .*\nnode kind: /]]) {
      await page.evaluate((n) => window.sarmapView.showOnly(n), name);
      const at = await page.evaluate((n) => window.sarmapView.screenPointOf(n, 0), name);
      await page.mouse.click(at.x, at.y);
      const text = await page.textContent('#sarmap-info');
      check(pattern.test(text || ''), `clicking one of the ${name} shows its id and class: '${text}'`);
    }
    await page.screenshot({ path: path.join(shots, 'node_clicked.png') });

    console.log(`viewer test: layers drew ${Object.entries(drawn).map(([n, p]) => `${n} ${p}`).join(', ')} pixels; ` +
      `${((Date.now() - started) / 1000).toFixed(1)} s; screenshots in ${shots}`);
  } finally {
    await browser.close();
  }
  console.log(`${checks - failures} passed, ${failures} failed`);
  return failures === 0 ? 0 : 1;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`FAIL: ${e && e.stack ? e.stack : e}`);
  process.exit(1);
});

// `foldfill view` on a 1M-triangle mesh: the time to write the page, its
// size, and the time from navigation to the first frame drawn in headless
// Chromium (software WebGL).
//   node bench/bench_view.mjs [FOLDFILL_BINARY] [--cells N] [--runs N]
// The mesh is generated: an N x N grid of folded cloth (N = 708: 1,002,528
// triangles) with a disk cut out, and its "fill", the same grid with the cut
// faces appended and marked as a binary PLY with foldfill_hole.
import {execFileSync} from 'node:child_process';
import {mkdtempSync, rmSync, statSync, writeFileSync} from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import {pathToFileURL} from 'node:url';

import {launch, missingBrowser, sourceDir} from '../tests/browser/browser.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(name);
  return at >= 0 ? Number(args.splice(at, 2)[1]) : fallback;
};
const cells = option('--cells', 708);
const runs = option('--runs', 3);
const binary = args[0] || path.join(sourceDir, 'build', 'foldfill');
const missing = missingBrowser();
if (missing) {
  console.error(`bench_view: ${missing}`);
  process.exit(1);
}

// A binary little-endian PLY of the grid; `filled`: every face, the cut ones
// last and marked with hole 1, else without the cut faces.
function writeGrid(file, filled) {
  const side = cells + 1;
  const vertexCount = side * side;
  const centre = cells / 2, radius = cells / 12;
  const kept = [], cut = [];
  for (let y = 0; y < cells; ++y) {
    for (let x = 0; x < cells; ++x) {
      const a = y * side + x, b = a + 1, c = a + side, d = c + 1;
      const inside = Math.hypot(x + 0.5 - centre, y + 0.5 - centre) < radius;
      (inside ? cut : kept).push([a, b, d], [a, d, c]);
    }
  }
  const faces = filled ? kept.concat(cut) : kept;
  const header = ['ply', 'format binary_little_endian 1.0', `element vertex ${vertexCount}`,
                  'property float x', 'property float y', 'property float z'];
  if (filled) header.push('property int foldfill_hole');
  header.push(`element face ${faces.length}`, 'property list uchar int vertex_indices');
  if (filled) header.push('property int foldfill_hole');
  header.push('end_header', '');
  const vertexBytes = filled ? 16 : 12, faceBytes = filled ? 17 : 13;
  const body = Buffer.alloc(vertexCount * vertexBytes + faces.length * faceBytes);
  let at = 0;
  const h = 1 / cells;
  for (let y = 0; y < side; ++y) {
    for (let x = 0; x < side; ++x) {
      body.writeFloatLE(x * h, at);
      body.writeFloatLE(y * h, at + 4);
      body.writeFloatLE(0.04 * Math.sin(x * h * 18) * (1 + 0.5 * Math.cos(y * h * 7)), at + 8);
      if (filled) body.writeInt32LE(-1, at + 12);
      at += vertexBytes;
    }
  }
  faces.forEach((face, f) => {
    body.writeUInt8(3, at);
    body.writeInt32LE(face[0], at + 1);
    body.writeInt32LE(face[1], at + 5);
    body.writeInt32LE(face[2], at + 9);
    if (filled) body.writeInt32LE(f >= kept.length ? 1 : -1, at + 13);
    at += faceBytes;
  });
  writeFileSync(file, Buffer.concat([Buffer.from(header.join('\n')), body]));
  return faces.length;
}

const dir = mkdtempSync(path.join(os.tmpdir(), 'foldfill_bench_view_'));
try {
  const input = path.join(dir, 'input.ply'), filled = path.join(dir, 'filled.ply');
  writeGrid(input, false);
  const triangles = writeGrid(filled, true);
  const page = path.join(dir, 'view.html');
  let start = performance.now();
  execFileSync(binary, ['view', input, filled, '-o', page], {stdio: 'inherit'});
  const writeSeconds = (performance.now() - start) / 1000;
  const pageBytes = statSync(page).size;

  const browser = await launch();
  const firstFrames = [], loads = [], steps = [];
  for (let run = 0; run < runs; ++run) {
    const tab = await browser.newPage();
    await tab.setViewport({width: 1280, height: 720});
    const errors = [];
    tab.on('pageerror', (error) => errors.push(error.message));
    start = performance.now();
    await tab.goto(pathToFileURL(page).href, {waitUntil: 'load', timeout: 120000});
    await tab.waitForFunction(() => window.foldfillView?.ready === true,
                              {timeout: 120000, polling: 50});
    loads.push((performance.now() - start) / 1000);
    // performance.now() in the page counts from its navigation's start.
    firstFrames.push(await tab.evaluate(() => window.foldfillView.firstFrameMs) / 1000);
    steps.push(await tab.evaluate(() => window.foldfillView.timings));
    if (errors.length) throw new Error(`page errors: ${errors.join('; ')}`);
    await tab.close();
  }
  await browser.close();
  const median = (values) => [...values].sort((a, b) => a - b)[Math.floor(values.length / 2)];
  console.log(JSON.stringify({
    triangles, page_bytes: pageBytes, write_seconds: +writeSeconds.toFixed(3),
    first_frame_seconds: firstFrames.map((s) => +s.toFixed(3)),
    first_frame_seconds_median: +median(firstFrames).toFixed(3),
    goto_to_ready_seconds_median: +median(loads).toFixed(3),
    // Milliseconds since navigation: script started (the HTML parsed), three.js
    // imported, buffers decoded, meshes set up, first frame drawn.
    steps_ms: steps.map((t) => Object.fromEntries(
        Object.entries(t).map(([step, ms]) => [step, Math.round(ms)]))),
  }));
  console.log(`${triangles} triangles: page ${(pageBytes / 1e6).toFixed(1)} MB written in ` +
              `${writeSeconds.toFixed(2)} s; first frame ${median(firstFrames).toFixed(2)} s ` +
              `after navigation (median of ${runs})`);
} finally {
  rmSync(dir, {recursive: true, force: true});
}

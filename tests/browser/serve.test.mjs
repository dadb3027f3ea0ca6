// `foldfill serve` in a real browser: the server on a free port, headless
// Chromium opens its page, uploads the demo's sheet, selects its hole by
// clicking it, fills, and the figures shown are the CLI's for the same
// settings; a long fill is cancelled; a bad upload shows the CLI's message;
// with obstacles and the Liepa comparison set, a patch point is dragged with
// the edit tool and undone.
//   node tests/browser/serve.test.mjs FOLDFILL_BINARY ARTEFACT_DIR
// Exits 77 (skipped, for CTest) with a message when Chromium, puppeteer-core,
// three.js or cpp-httplib is missing. Screenshots are left in ARTEFACT_DIR.
import assert from 'node:assert/strict';
import {execFileSync, spawn, spawnSync} from 'node:child_process';
import {mkdirSync, readFileSync, rmSync, writeFileSync} from 'node:fs';
import path from 'node:path';
import {after, before, test} from 'node:test';

import {capture, coveredShare, launch, missingBrowser} from './browser.mjs';

if (process.argv.length < 4) {
  console.error('usage: node serve.test.mjs FOLDFILL_BINARY ARTEFACT_DIR');
  process.exit(2);
}
// Absolute: some runs are in the data folder.
const [binary, artefacts] = process.argv.slice(2, 4).map((p) => path.resolve(p));
const skip = (why) => {
  console.log(`skipped: ${why}`);
  process.exit(77);
};
const missing = missingBrowser();
if (missing) skip(missing);
// A mesh that is not there: a build without the server says so before reading it.
const probe = spawnSync(binary, ['serve', '/nonexistent/none.obj'], {encoding: 'utf8'});
if (/not available/.test(probe.stderr)) skip(probe.stderr.trim());

rmSync(artefacts, {recursive: true, force: true});
mkdirSync(artefacts, {recursive: true});
const data = path.join(artefacts, 'data');
// Run in `data`, so that messages name the files as the page does (by name).
const run = (...args) => execFileSync(binary, args, {cwd: data, encoding: 'utf8',
                                                     stdio: ['ignore', 'pipe', 'pipe']});
execFileSync(binary, ['demo', data, '--quiet'], {stdio: ['ignore', 'pipe', 'pipe']});
const input = path.join(data, 'input.obj');
const bad = path.join(data, 'bad.obj');
writeFileSync(bad, 'v 0 0 0\nv 1 0 0\nf 1 2 7\n');
const badRun = spawnSync(binary, ['holes', 'bad.obj'], {cwd: data, encoding: 'utf8'});
const cliMessage = badRun.stderr.trim().replace(/^foldfill: error: /, '');
assert.match(cliMessage, /^bad\.obj: /);

let server, url, browser;
before(async () => {
  server = spawn(binary, ['serve', '--port', '0'], {stdio: ['ignore', 'pipe', 'inherit']});
  url = await new Promise((resolve, reject) => {
    let text = '';
    server.stdout.on('data', (chunk) => {
      text += chunk;
      const found = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (found) resolve(found[0]);
    });
    server.on('exit', (code) => reject(new Error(`serve exited with ${code}`)));
  });
  browser = await launch();
});
after(async () => {
  await browser?.close();
  server?.kill();
});

async function open() {
  const tab = await browser.newPage();
  await tab.setViewport({width: 1300, height: 800});
  const problems = [];
  tab.on('console', (message) => {
    // The bad upload's 400 is logged by Chromium as a failed resource.
    if (message.type() === 'error' && !/status of 400/.test(message.text()))
      problems.push(`console: ${message.text()}`);
  });
  tab.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
  await tab.goto(url, {waitUntil: 'load'});
  await tab.waitForFunction(() => window.foldfillServe?.ready === true, {timeout: 60000});
  return {tab, problems};
}

async function upload(tab, file) {
  const chooser = await tab.$('#file');
  await chooser.uploadFile(file);
}

async function fillAndWait(tab) {
  const job = await tab.evaluate(() => window.foldfillServe.job);
  await tab.click('#fill');
  await tab.waitForFunction((n) => window.foldfillServe.job > n, {timeout: 20000}, job);
  await tab.waitForFunction(() => !window.foldfillServe.running && window.foldfillServe.result,
                            {timeout: 300000});
}

test('a bad upload shows the message of the CLI', async () => {
  const {tab, problems} = await open();
  await upload(tab, bad);
  await tab.waitForFunction(() => window.foldfillServe.error !== null, {timeout: 20000});
  const shown = await tab.$eval('#error', (e) => (e.hidden ? '' : e.textContent));
  assert.equal(shown, cliMessage);
  await tab.screenshot({path: path.join(artefacts, 'serve-bad-upload.png')});
  assert.deepEqual(problems, []);
  await tab.close();
});

test('upload, select the hole by clicking it, fill: the figures are the CLI\'s', async () => {
  const {tab, problems} = await open();
  await upload(tab, input);
  await tab.waitForFunction(() => window.foldfillServe.mesh !== null, {timeout: 60000});
  const {loops, hole} = await tab.evaluate(() => {
    const mesh = window.foldfillServe.mesh;
    return {loops: mesh.loops.length, hole: mesh.loops.find((l) => l.kind === 'hole').id};
  });
  assert.equal(loops, 2);
  // The mesh is drawn.
  const image = await capture(tab);
  const box = await tab.$eval('#canvas', (c) => {
    const r = c.getBoundingClientRect();
    return {x0: r.left, x1: r.right, y0: r.top, y1: r.bottom};
  });
  assert.ok(coveredShare(image, box) > 0.1, 'the canvas shows the mesh');
  // A click on the hole's id in the picture selects it alone.
  await tab.waitForSelector(`.loop-label[data-loop="${hole}"]`);
  await tab.click(`.loop-label[data-loop="${hole}"]`);
  const selected = await tab.evaluate(() => [...window.foldfillServe.selected]);
  assert.deepEqual(selected, [hole]);
  assert.equal(await tab.$eval(`#loop-list li[data-loop="${hole}"]`, (li) => li.className),
               'selected');
  await tab.screenshot({path: path.join(artefacts, 'serve-selected.png')});
  await fillAndWait(tab);
  await tab.screenshot({path: path.join(artefacts, 'serve-filled.png')});

  run('fill', 'input.obj', '-o', 'cli.obj', '--holes', String(hole), '--report', 'cli.json',
      '--quiet');
  const report = JSON.parse(readFileSync(path.join(data, 'cli.json'), 'utf8'));
  const expected = report.holes.find((h) => h.loop_id === hole);
  const shown = async (column) =>
    tab.$eval(`#report-table tr[data-loop="${hole}"] td[data-column="${column}"]`,
              (td) => td.textContent);
  assert.equal(await shown('status'), 'filled');
  assert.equal(Number(await shown('patch vertices')), expected.patch_vertex_count);
  assert.equal(Number(await shown('patch faces')), expected.patch_face_count);
  assert.equal(Number(await shown('iterations')), expected.iterations);
  assert.equal(await shown('energy'), expected.energy.final.total.toPrecision(5));
  assert.equal(await shown('area / flat'), expected.area_ratio_to_flat.toPrecision(5));
  // The API's report is the CLI's.
  const api = await tab.evaluate(() => window.foldfillServe.result.report);
  assert.deepEqual(api.counts, report.counts);
  assert.deepEqual(problems, []);
  await tab.close();
});

test('a long fill shows its progress and is cancelled', async () => {
  const {tab, problems} = await open();
  await upload(tab, input);
  await tab.waitForFunction(() => window.foldfillServe.mesh !== null, {timeout: 60000});
  await tab.$eval('#density', (e) => { e.value = '12'; });
  await tab.click('#fill');
  await tab.waitForFunction(() => /iteration [1-9]/.test(document.getElementById('progress').textContent),
                            {timeout: 120000});
  assert.equal(await tab.$eval('#cancel', (b) => b.disabled), false);
  await tab.click('#cancel');
  await tab.waitForFunction(() => !window.foldfillServe.running && window.foldfillServe.result,
                            {timeout: 60000});
  assert.match(await tab.$eval('#progress', (e) => e.textContent), /^cancelled/);
  assert.equal(await tab.evaluate(() => window.foldfillServe.result.report.cancelled), true);
  await tab.screenshot({path: path.join(artefacts, 'serve-cancelled.png')});
  assert.deepEqual(problems, []);
  await tab.close();
});

// The result's positions as the server has them now.
async function serverPositions(tab) {
  return tab.evaluate(async () => {
    const reply = await (await fetch('/api/result')).json();
    const binary = atob(reply.positions);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
    return {positions: Array.from(new Float32Array(bytes.buffer)), report: reply.report};
  });
}

test('obstacles, Liepa side by side, and the edit tool drags a patch point', async () => {
  const {tab, problems} = await open();
  await tab.setViewport({width: 1000, height: 640});
  await upload(tab, input);
  await tab.waitForFunction(() => window.foldfillServe.mesh !== null, {timeout: 60000});
  // A plane under the sheet, drawn in the view and passed to the fill.
  await tab.$eval('#obstacles-json', (e) => {
    e.value = '{"obstacles": [{"type": "plane", "point": [0, 0, -0.6], "normal": [0, 0, 1]}]}';
  });
  await tab.click('#set-obstacles');
  await tab.waitForFunction(() => window.foldfillServe.obstacles.length === 1, {timeout: 20000});
  await tab.click('#compare-liepa');
  await fillAndWait(tab);
  await tab.waitForFunction(() => window.foldfillServe.liepa !== null, {timeout: 120000});
  assert.equal(await tab.evaluate(() => window.foldfillServe.result.report.options.obstacles), 1);
  assert.equal(await tab.$eval('#stage2', (e) => e.hidden), false);
  assert.equal(await tab.evaluate(() => window.foldfillServe.liepa.report.options.method), 'liepa');
  const image = await capture(tab);
  const right = await tab.$eval('#canvas2', (c) => {
    const r = c.getBoundingClientRect();
    return {x0: r.left, x1: r.right, y0: r.top, y1: r.bottom};
  });
  // The Liepa panel is read from the page as a whole (its own canvas).
  assert.ok(right.x1 - right.x0 > 100, 'the Liepa panel has room');
  assert.ok(coveredShare(image, {x0: image.offset.left, x1: right.x0, y0: right.y0, y1: right.y1}) > 0.05);

  const before = await serverPositions(tab);
  const inputCount = await tab.evaluate(() => window.foldfillServe.mesh.vertex_count);
  const hole = before.report.holes[0];
  assert.equal(hole.self_intersections, 0);
  // The new vertex nearest the patch's centroid, on the page.
  const [first, end] = hole.new_vertices;
  const centre = [0, 1, 2].map((c) => {
    let sum = 0;
    for (let v = first; v < end; ++v) sum += before.positions[v * 3 + c];
    return sum / (end - first);
  });
  let handle = first, nearest = Infinity;
  for (let v = first; v < end; ++v) {
    const d = [0, 1, 2].reduce((a, c) => a + (before.positions[v * 3 + c] - centre[c]) ** 2, 0);
    if (d < nearest) { nearest = d; handle = v; }
  }
  const at = await tab.evaluate((v) => window.foldfillServe.screenOf(v), handle);
  assert.ok(at, 'the handle is in view');
  await tab.click('#edit');
  await tab.mouse.move(at.x, at.y);
  await tab.mouse.down();
  for (let k = 1; k <= 10; ++k) {
    await tab.mouse.move(at.x, at.y - 3 * k);
    await new Promise((resolve) => setTimeout(resolve, 60));
  }
  await tab.mouse.up();
  await tab.waitForFunction(() => window.foldfillServe.edit.ends === 1, {timeout: 60000});
  assert.ok(await tab.evaluate(() => window.foldfillServe.edit.moves) > 0, 'moves were sent');
  const after = await serverPositions(tab);
  // The input's vertices did not move; the patch did; nothing crosses.
  assert.deepEqual(after.positions.slice(0, inputCount * 3), before.positions.slice(0, inputCount * 3));
  let moved = 0;
  for (let i = first * 3; i < end * 3; ++i) moved = Math.max(moved, Math.abs(after.positions[i] - before.positions[i]));
  assert.ok(moved > 0.01, `the patch moved (${moved})`);
  assert.equal(after.report.holes[0].self_intersections, 0);
  assert.equal(await tab.$eval(`#report-table tr[data-loop="${hole.loop_id}"] td[data-column="crossings"]`,
                               (td) => td.textContent), '0');
  // The page shows what the server has.
  const shown = await tab.evaluate((v) => Array.from(window.foldfillServe.result.vertexPositions.slice(v * 3, v * 3 + 3)),
                                   handle);
  assert.deepEqual(shown, after.positions.slice(handle * 3, handle * 3 + 3));
  await tab.screenshot({path: path.join(artefacts, 'serve-edited.png')});

  // Undo: the fill's state, bit for bit.
  assert.equal(await tab.$eval('#undo', (b) => b.disabled), false);
  await tab.click('#undo');
  await tab.waitForFunction(() => window.foldfillServe.edit.undos === 1, {timeout: 20000});
  const undone = await serverPositions(tab);
  assert.deepEqual(undone.positions, before.positions);
  assert.equal(await tab.$eval('#undo', (b) => b.disabled), true);
  assert.deepEqual(problems, []);
  await tab.close();
});

// `foldfill view` in a real browser: headless Chromium loads the page from
// file://, shows the meshes, and its controls change the picture.
//   node tests/browser/view.test.mjs FOLDFILL_BINARY ARTEFACT_DIR
// Exits 77 (skipped, for CTest) with a message when Chromium, puppeteer-core
// or the build's three.js is missing. Screenshots are left in ARTEFACT_DIR.
import assert from 'node:assert/strict';
import {execFileSync, spawnSync} from 'node:child_process';
import {mkdirSync, rmSync, statSync, writeFileSync} from 'node:fs';
import path from 'node:path';
import {after, before, test} from 'node:test';
import {pathToFileURL} from 'node:url';

import {capture, changedShare, coveredShare, launch, missingBrowser, nextFrame} from './browser.mjs';

const [binary, artefacts] = process.argv.slice(2);
if (!binary || !artefacts) {
  console.error('usage: node view.test.mjs FOLDFILL_BINARY ARTEFACT_DIR');
  process.exit(2);
}
const skip = (why) => {
  console.log(`skipped: ${why}`);
  process.exit(77);
};
const missing = missingBrowser();
if (missing) skip(missing);

rmSync(artefacts, {recursive: true, force: true});
mkdirSync(artefacts, {recursive: true});
const data = path.join(artefacts, 'data');
const run = (...args) => execFileSync(binary, args, {encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe']});

// The demo's folded sheet, its fill (OBJ: new faces found past the input's
// count) and the same fill as PLY (new faces from its foldfill_hole marks).
run('demo', data, '--quiet');
const input = path.join(data, 'input.obj');
const filledObj = path.join(data, 'filled.obj');
const filledPly = path.join(data, 'filled.ply');
run('fill', input, '-o', filledPly, '--quiet');
const page = path.join(artefacts, 'view.html');
const probe = spawnSync(binary, ['view', input, filledObj, '-o', page, '--report',
                                 path.join(data, 'report.json')], {encoding: 'utf8'});
if (probe.status !== 0 && /not available/.test(probe.stderr)) skip(probe.stderr.trim());
assert.equal(probe.status, 0, probe.stderr);

// A coarse torus with one square hole, and its fill (the two faces put
// back, last): flat and smooth shading differ plainly on it.
function writeTorus(file, withHole, filled) {
  const around = 16, across = 8, lines = [];
  for (let i = 0; i < around; ++i) {
    for (let j = 0; j < across; ++j) {
      const u = 2 * Math.PI * i / around, v = 2 * Math.PI * j / across;
      const r = 1 + 0.45 * Math.cos(v);
      lines.push(`v ${r * Math.cos(u)} ${0.45 * Math.sin(v)} ${r * Math.sin(u)}`);
    }
  }
  const faces = [], hole = [];
  for (let i = 0; i < around; ++i) {
    for (let j = 0; j < across; ++j) {
      const a = i * across + j, b = ((i + 1) % around) * across + j;
      const c = i * across + (j + 1) % across, d = ((i + 1) % around) * across + (j + 1) % across;
      const quad = [[a + 1, c + 1, d + 1], [a + 1, d + 1, b + 1]];
      (withHole && i === 3 && j === 1 ? hole : faces).push(...quad);
    }
  }
  for (const f of filled ? faces.concat(hole) : faces) lines.push(`f ${f.join(' ')}`);
  writeFileSync(file, lines.join('\n') + '\n');
}
const torus = path.join(data, 'torus.obj'), torusFilled = path.join(data, 'torus_filled.obj');
writeTorus(torus, true, false);
writeTorus(torusFilled, true, true);
const torusPage = path.join(artefacts, 'view-torus.html');
run('view', torus, torusFilled, '-o', torusPage);


let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

// Opens a page, keeping its console errors, failed loads and what it fetched.
async function open(file, viewport = {width: 1200, height: 700}) {
  const tab = await browser.newPage();
  await tab.setViewport(viewport);
  const problems = [];
  const fetched = [];
  tab.on('console', (message) => {
    if (message.type() === 'error') problems.push(`console: ${message.text()}`);
  });
  tab.on('pageerror', (error) => problems.push(`page error: ${error.message}`));
  tab.on('requestfailed', (request) => problems.push(`failed: ${request.url()}`));
  tab.on('request', (request) => fetched.push(request.url()));
  await tab.goto(pathToFileURL(file).href, {waitUntil: 'load'});
  await tab.waitForFunction(() => window.foldfillView?.ready === true, {timeout: 60000});
  return {tab, problems, fetched};
}

async function shot(tab, name) {
  await tab.screenshot({path: path.join(artefacts, `${name}.png`)});
}

// Clicks a control and waits for the picture drawn after it.
async function click(tab, selector) {
  const frames = await tab.evaluate(() => window.foldfillView.frames);
  await tab.click(selector);
  await nextFrame(tab, frames);
  return capture(tab);
}

test('the page loads offline with no console error and shows every mesh', async () => {
  const {tab, problems, fetched} = await open(page);
  await shot(tab, 'view-start');
  assert.deepEqual(problems, []);
  for (const url of fetched) assert.match(url, /^(file|blob|data):/, `fetched ${url}`);
  const image = await capture(tab);
  const boxes = await tab.evaluate(() => window.foldfillView.screenBoxes());
  assert.equal(boxes.length, 2);
  for (const box of boxes) {
    assert.ok(box.x1 - box.x0 > 50 && box.y1 - box.y0 > 50, `${box.name} is on screen`);
    const share = coveredShare(image, box);
    assert.ok(share > 0.2, `${box.name}: ${share} of its screen area shows the mesh`);
  }
  // The hole is open on the left and filled on the right.
  assert.ok(changedShare(image, image) === 0);
  const left = {...boxes[0]}, right = {...boxes[1]};
  assert.ok(Math.abs(coveredShare(image, left) - coveredShare(image, right)) > 0.002,
            'the filled mesh covers more than the input');
  // Every hole filled has a colour key and a row of the report.
  const key = await tab.$eval('#holes-key', (e) => e.textContent);
  assert.match(key, /hole \d+/);
  const rows = await tab.$$eval('#report-table tr[data-loop]', (trs) => trs.length);
  assert.ok(rows >= 1, 'the report table has a row per hole');
  const labels = await tab.$$eval('.loop-label', (ls) => ls.filter((l) => !l.hidden).length);
  assert.ok(labels >= 1, 'the loops have their ids on screen');
  await tab.close();
});

test('each toggle changes the picture', async () => {
  const {tab, problems} = await open(torusPage);
  assert.match(await tab.$eval('#holes-key', (e) => e.textContent), /hole 0/,
               'the faces past the input\'s fill loop 0');
  let before = await capture(tab);
  const toggles = [
    ['#wireframe', 'view-wireframe'],
    ['#wireframe', null],
    ['#flat', 'view-flat'],
    ['#colour-gaussian', 'view-gaussian'],
    ['#colour-mean', 'view-mean'],
    ['#colour-holes', null],
    ['#loops', 'view-no-loops'],
    ['#layout-overlay', 'view-overlay'],
    ['#show-0', 'view-overlay-input'],
    ['#layout-side', null],
  ];
  for (const [selector, name] of toggles) {
    const after = await click(tab, selector);
    const share = changedShare(before, after);
    assert.ok(share > 0.001, `${selector} changed ${share} of the picture`);
    if (name) await shot(tab, name);
    before = after;
  }
  const legend = await tab.$eval('#legend', (e) => e.hidden);
  assert.equal(legend, true, 'no legend with the holes colours');
  assert.deepEqual(problems, []);
  await tab.close();
});

test('one camera for both panels: a drag turns both, the wheel zooms both', async () => {
  const {tab, problems} = await open(page);
  const start = await capture(tab);
  const box = await tab.$eval('#canvas', (c) => {
    const r = c.getBoundingClientRect();
    return {x: r.left, y: r.top, width: r.width, height: r.height};
  });
  let frames = await tab.evaluate(() => window.foldfillView.frames);
  await tab.mouse.move(box.x + box.width * 0.25, box.y + box.height * 0.5);
  await tab.mouse.down();
  await tab.mouse.move(box.x + box.width * 0.25 + 120, box.y + box.height * 0.5 + 40, {steps: 5});
  await tab.mouse.up();
  await nextFrame(tab, frames);
  const turned = await capture(tab);
  await shot(tab, 'view-turned');
  assert.ok(changedShare(start, turned, 0, 0.5) > 0.01, 'the left panel turned');
  assert.ok(changedShare(start, turned, 0.5, 1) > 0.01, 'the right panel turned with it');
  frames = await tab.evaluate(() => window.foldfillView.frames);
  await tab.mouse.move(box.x + box.width * 0.75, box.y + box.height * 0.5);
  await tab.mouse.wheel({deltaY: -400});
  await nextFrame(tab, frames);
  const zoomed = await capture(tab);
  assert.ok(changedShare(turned, zoomed, 0, 0.5) > 0.01, 'the left panel zoomed');
  assert.ok(changedShare(turned, zoomed, 0.5, 1) > 0.01, 'the right panel zoomed');
  frames = await tab.evaluate(() => window.foldfillView.frames);
  await tab.keyboard.down('Shift');
  await tab.mouse.move(box.x + box.width * 0.75, box.y + box.height * 0.5);
  await tab.mouse.down();
  await tab.mouse.move(box.x + box.width * 0.75 - 80, box.y + box.height * 0.5, {steps: 4});
  await tab.mouse.up();
  await tab.keyboard.up('Shift');
  await nextFrame(tab, frames);
  assert.ok(changedShare(zoomed, await capture(tab)) > 0.01, 'shift-drag panned');
  assert.deepEqual(problems, []);
  await tab.close();
});

test('a fill read from PLY colours its new faces from its marks', async () => {
  const plyPage = path.join(artefacts, 'view-ply.html');
  run('view', input, filledPly, '-o', plyPage, '--layout', 'overlay');
  const {tab, problems} = await open(plyPage, {width: 800, height: 600});
  await shot(tab, 'view-ply');
  assert.deepEqual(problems, []);
  const image = await capture(tab);
  const boxes = await tab.evaluate(() => window.foldfillView.screenBoxes());
  assert.equal(boxes.length, 1, 'overlaid: one panel');
  assert.ok(coveredShare(image, boxes[0]) > 0.2);
  assert.match(await tab.$eval('#holes-key', (e) => e.textContent), /hole \d+/);
  // T switches the overlaid mesh to the input.
  const frames = await tab.evaluate(() => window.foldfillView.frames);
  await tab.keyboard.press('t');
  await nextFrame(tab, frames);
  assert.ok(changedShare(image, await capture(tab)) > 0.001, 'T switched the mesh');
  await tab.close();
});

test('the page is one file, with the meshes as binary buffers', () => {
  const size = statSync(page).size;
  assert.ok(size > 500000, 'three.js is inlined');
  assert.ok(size < 5000000, `the demo's page is ${size} bytes`);
});

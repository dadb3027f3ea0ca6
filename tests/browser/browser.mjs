// Shared by the browser tests and the view benchmark: headless Chromium from
// Debian driven by puppeteer-core (no browser download), and reading the
// page's canvas back.
import {existsSync} from 'node:fs';
import {createRequire} from 'node:module';
import path from 'node:path';
import {fileURLToPath} from 'node:url';

export const sourceDir = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

// Why the browser tests cannot run here, or null when they can.
export function missingBrowser() {
  const chromium = chromiumPath();
  if (!chromium) return 'no Chromium (apt-get install chromium, or set FOLDFILL_CHROMIUM)';
  try {
    createRequire(path.join(sourceDir, 'package.json')).resolve('puppeteer-core');
  } catch {
    return `no puppeteer-core in ${sourceDir}/node_modules (run npm ci there, or bash scripts/setup.sh)`;
  }
  return null;
}

export function chromiumPath() {
  const candidates = [process.env.FOLDFILL_CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser'];
  return candidates.find((candidate) => candidate && existsSync(candidate)) || null;
}

export async function launch() {
  const require = createRequire(path.join(sourceDir, 'package.json'));
  const puppeteer = (await import(require.resolve('puppeteer-core'))).default;
  // Software WebGL (SwiftShader), as on a machine without a GPU; no sandbox
  // (the tests run as root in CI) and none of Chromium's background traffic.
  return puppeteer.launch({
    executablePath: chromiumPath(),
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--disable-dev-shm-usage', '--disable-background-networking',
           '--disable-component-update', '--disable-sync', '--disable-quic', '--no-first-run',
           '--disable-extensions'],
  });
}

// The canvas's pixels as RGBA bytes, with its size and its pixels per CSS pixel.
export async function capture(page) {
  const {width, height, scale, base64} = await page.evaluate(() => {
    const canvas = document.getElementById('canvas');
    const copy = document.createElement('canvas');
    copy.width = canvas.width;
    copy.height = canvas.height;
    const context = copy.getContext('2d');
    context.drawImage(canvas, 0, 0);
    const data = context.getImageData(0, 0, copy.width, copy.height).data;
    let text = '';
    for (let i = 0; i < data.length; i += 0x8000) {
      text += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
    }
    return {width: copy.width, height: copy.height, scale: canvas.width / canvas.clientWidth,
            base64: btoa(text)};
  });
  const offset = await page.evaluate(() => {
    const box = document.getElementById('canvas').getBoundingClientRect();
    return {left: box.left, top: box.top};
  });
  return {width, height, scale, offset, data: Buffer.from(base64, 'base64')};
}

const BACKGROUND = [0xf4, 0xf4, 0xf2];

// The share of the pixels of a page rectangle (CSS pixels) that are not the background.
export function coveredShare(image, box) {
  const x0 = Math.max(0, Math.floor((box.x0 - image.offset.left) * image.scale));
  const x1 = Math.min(image.width, Math.ceil((box.x1 - image.offset.left) * image.scale));
  const y0 = Math.max(0, Math.floor((box.y0 - image.offset.top) * image.scale));
  const y1 = Math.min(image.height, Math.ceil((box.y1 - image.offset.top) * image.scale));
  let covered = 0, all = 0;
  for (let y = y0; y < y1; ++y) {
    for (let x = x0; x < x1; ++x) {
      const i = (y * image.width + x) * 4;
      ++all;
      if (Math.abs(image.data[i] - BACKGROUND[0]) + Math.abs(image.data[i + 1] - BACKGROUND[1]) +
          Math.abs(image.data[i + 2] - BACKGROUND[2]) > 24) ++covered;
    }
  }
  return all === 0 ? 0 : covered / all;
}

// The share of pixels that differ between two captures (in a column range
// of the canvas, as shares of its width).
export function changedShare(a, b, from = 0, to = 1) {
  if (a.width !== b.width || a.height !== b.height) return 1;
  const x0 = Math.floor(from * a.width), x1 = Math.floor(to * a.width);
  let changed = 0;
  for (let y = 0; y < a.height; ++y) {
    for (let x = x0; x < x1; ++x) {
      const i = (y * a.width + x) * 4;
      if (Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) +
          Math.abs(a.data[i + 2] - b.data[i + 2]) > 12) ++changed;
    }
  }
  return changed / ((x1 - x0) * a.height);
}

// Waits until the page drew a frame after `frames` (its count before a change).
export async function nextFrame(page, frames) {
  await page.waitForFunction((n) => window.foldfillView.frames > n, {timeout: 20000}, frames);
}

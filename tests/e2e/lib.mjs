// What the browser test and the bench share: launching Chromium, reading the
// canvas, waiting for the page to show a snapshot.
import { chromium } from 'playwright-core';

export const CHROMIUM = process.env.GER_CHROMIUM || '/usr/bin/chromium';

export function fail(message) {
  throw new Error(message);
}

/** Runs one named check, saying how it went. */
export async function step(name, check) {
  const start = performance.now();
  try {
    await check();
    console.log(`ok   ${name} (${Math.round(performance.now() - start)} ms)`);
  } catch (error) {
    console.log(`FAIL ${name}: ${error.message}`);
    throw error;
  }
}

/** A headless Chromium with WebGL2 on the CPU (SwiftShader), since test
 *  machines have no GPU, and a page whose errors are collected. */
export async function launch({ width = 1400, height = 860 } = {}) {
  const browser = await chromium.launch({
    executablePath: CHROMIUM,
    args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
  });
  const page = await browser.newPage({ viewport: { width, height } });
  const errors = [];
  page.on('pageerror', (error) => errors.push(String(error)));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
  });
  return { browser, page, errors };
}

/** Waits until the page has drawn snapshot `version` or a later one. */
export async function waitShown(page, version, timeout = 30000) {
  await page.waitForFunction((v) => Number(document.body.dataset.shown) >= v, version, { timeout, polling: 'raf' });
}

/** Counts the canvas's pixels that are not background, those of the
 *  selection's colour (#ffb000), those of the fixtures' green (#78d959),
 *  and the greens (the design layer's "within the tolerance" among them). */
export async function canvasPixels(page) {
  return page.evaluate(() => {
    const canvas = document.getElementById('view');
    const copy = document.createElement('canvas');
    copy.width = canvas.width;
    copy.height = canvas.height;
    const g = copy.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const d = g.getImageData(0, 0, copy.width, copy.height).data;
    let drawn = 0, highlight = 0, fixture = 0, within = 0;
    for (let i = 0; i < d.length; i += 4) {
      const [r, gr, b] = [d[i], d[i + 1], d[i + 2]];
      if (Math.abs(r - 27) + Math.abs(gr - 30) + Math.abs(b - 35) > 24) drawn++;
      if (r > 220 && gr > 140 && gr < 200 && b < 70) highlight++;
      if (gr > 150 && gr > r + 50 && gr > b + 60) fixture++;
      if (gr > 60 && gr > r + 30 && gr > b + 30) within++;
    }
    return { drawn, highlight, fixture, within, total: d.length / 4 };
  });
}

/** The snapshot and its toolpath, fetched from the server as the page does. */
export async function fetchData(page) {
  return page.evaluate(async () => {
    for (;;) {
      const state = await (await fetch('/api/state')).json();
      const response = await fetch(`/api/path?version=${state.version}`);
      if (response.status === 410) continue;
      const buffer = await response.arrayBuffer();
      const f = new Float32Array(buffer), u = new Uint32Array(buffer);
      const pieces = [];
      for (let i = 0; i < f.length / 8; i++) {
        const [x0, y0, z0, x1, y1, z1] = f.subarray(i * 8, i * 8 + 6);
        pieces.push({ x0, y0, z0, x1, y1, z1, line: u[i * 8 + 6], kind: u[i * 8 + 7] });
      }
      return { state, pieces };
    }
  });
}

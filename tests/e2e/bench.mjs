// The page's bench, in a real headless Chromium against a running `ger view`
// (host/bench/view-page.sh starts the server and runs this).
//
//   node bench.mjs live URL PROGRAM [REPEATS]   keystroke → new version on screen; file written → on screen
//   node bench.mjs load URL                     navigation → first full draw
//
// "On screen" is the page's own mark: the frame in which the text, the output
// pane and the 3D view of a snapshot have all been drawn (body[data-shown]).
import fs from 'node:fs';
import { launch, fail } from './lib.mjs';

const [mode, url, program, repeatsArg] = process.argv.slice(2);
const repeats = Number(repeatsArg || 5);
if (!['live', 'load'].includes(mode) || !url || (mode === 'live' && !program)) {
  fail('usage: node bench.mjs live URL PROGRAM [REPEATS] | node bench.mjs load URL');
}

// Times in the page: the last keydown, and every snapshot the page shows.
function instrument() {
  window.__bench = { key: 0, shown: [] };
  document.addEventListener('keydown', () => (window.__bench.key = performance.now()), true);
  document.addEventListener('DOMContentLoaded', () => {
    new MutationObserver(() => {
      window.__bench.shown.push({ version: Number(document.body.dataset.shown), at: performance.now(), now: Date.now() });
    }).observe(document.body, { attributes: true, attributeFilter: ['data-shown'] });
  });
}

const shownAfter = (page, version) =>
  page
    .waitForFunction((v) => window.__bench.shown.find((s) => s.version > v), version, { timeout: 120000 })
    .then((handle) => handle.jsonValue());

const latest = (page) => page.evaluate(() => Number(document.body.dataset.shown || 0));

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const report = (name, xs) =>
  console.log(`${name}: median ${Math.round(median(xs))} ms (runs: ${xs.map((x) => Math.round(x)).join(', ')})`);

const { browser, page, errors } = await launch();
await page.addInitScript(instrument);
try {
  if (mode === 'load') {
    await page.goto(url);
    const first = await shownAfter(page, 0);
    const state = await page.evaluate(async () => {
      const s = await (await fetch('/api/state')).json();
      return { lines: s.output.source_lines.length, elapsed: s.elapsed_ms, path: s.path, part: s.part };
    });
    console.log(
      `first full draw: ${Math.round(first.at)} ms after navigation ` +
        `(${state.lines.toLocaleString()} output lines; ${state.path.pieces.toLocaleString()} of ` +
        `${state.path.total.toLocaleString()} pieces sent${state.path.decimated ? ', decimated' : ''}; ` +
        `heights ${state.part ? `${state.part.nx} × ${state.part.ny}` : 'none'}; server's snapshot took ${state.elapsed} ms)`,
    );
    // Scrolling the output to its end stays a matter of one frame.
    const scroll = await page.evaluate(async () => {
      const out = document.getElementById('output');
      const start = performance.now();
      out.scrollTop = out.scrollHeight;
      await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
      return { ms: performance.now() - start, rows: out.querySelectorAll('.vrow').length };
    });
    console.log(`scroll the output to its end: ${Math.round(scroll.ms)} ms to the next frame, ${scroll.rows} rows in the DOM`);
  } else {
    await page.goto(url);
    await shownAfter(page, 0);
    const original = fs.readFileSync(program, 'utf8');

    // The file written on disk (before any edit in the page, which would make
    // the server see a conflict instead).
    const disk = [];
    for (let i = 0; i < repeats; i++) {
      const before = await latest(page);
      const text = original.replace(/\n(G0?1 X)(\d)/, (_, g, d) => `\n${g}${(Number(d) + i + 1) % 10}`);
      const start = Date.now();
      fs.writeFileSync(program, text);
      const shown = await shownAfter(page, before);
      disk.push(shown.now - start);
      await page.evaluate(() => (window.__bench.shown = []));
    }
    report('file written on disk → page shows it', disk);
    fs.writeFileSync(program, original);
    await page.waitForTimeout(1000);

    // A keystroke: the digit after "X" of the first G01 X… line, replaced.
    const textarea = page.locator('#sourceText');
    await textarea.click();
    const keys = [];
    for (let i = 0; i < repeats; i++) {
      await page.waitForTimeout(400);
      const before = await latest(page);
      await textarea.evaluate((t) => {
        const at = t.value.search(/\nG0?1 X\d/) + t.value.slice(t.value.search(/\nG0?1 X\d/)).indexOf('X') + 1;
        t.setSelectionRange(at, at + 1);
      });
      await page.evaluate(() => (window.__bench.shown = []));
      await page.keyboard.press(String((i + 3) % 10));
      const shown = await shownAfter(page, before);
      keys.push(shown.at - (await page.evaluate(() => window.__bench.key)));
    }
    report('keystroke → output and 3D view show the new version', keys);
  }
  if (errors.length) fail(`the page reported errors:\n${errors.join('\n')}`);
} finally {
  await browser.close();
}

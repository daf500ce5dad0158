// The browser test of `ger view`: drives a real headless Chromium through the
// page the way a user would, against a running server.
//
//   node view.mjs URL SCREENSHOT [PROGRAM]
//
// URL is the page `ger view` printed; SCREENSHOT where to write a picture of
// the page; PROGRAM, if given, the file the server views (the test then saves
// an edit with Ctrl-S and checks the file). Run by host/tests/view.rs.
import { launch, fail, step, canvasPixels, waitShown, fetchData } from './lib.mjs';
import fs from 'node:fs';

const [url, screenshot, program] = process.argv.slice(2);
if (!url || !screenshot) fail('usage: node view.mjs URL SCREENSHOT [PROGRAM]');

const { browser, page, errors } = await launch();
try {
  await step('the page opens and shows a snapshot', async () => {
    await page.goto(url);
    // Generous: on a fresh machine the first snapshot waits for the example's
    // wizards to be built.
    await waitShown(page, 1, 300000);
    if (await page.locator('#noGl').isVisible()) fail('this Chromium gives the page no WebGL2');
  });

  const { state, pieces } = await fetchData(page);

  await step('the 3D view has drawn the part', async () => {
    const { drawn, total, highlight } = await canvasPixels(page);
    if (drawn < total * 0.05) fail(`only ${drawn} of ${total} canvas pixels differ from the background`);
    if (highlight) fail(`${highlight} pixels have the selection's colour before anything is selected`);
  });

  await step('the fixture of the config is drawn by its edges in green', async () => {
    if (state.fixtures.length !== 1 || state.fixtures[0].name !== 'jaw') fail(`the snapshot's fixtures: ${JSON.stringify(state.fixtures)}`);
    const { fixture } = await canvasPixels(page);
    if (fixture < 40) fail(`the view shows ${fixture} pixels of the fixtures' green`);
  });

  await step('D shows the part against its design, its own part: within the tolerance, green', async () => {
    // The design is ger render's STL of the part at a finer grid: only the cells along the walls differ.
    const d = state.design;
    if (!d || d.gouge.area + d.left.area > 0.05 * d.judged_area) fail(`the snapshot's design: ${JSON.stringify(d)}`);
    const before = await canvasPixels(page);
    await page.locator('#view').focus();
    await page.keyboard.press('d');
    await page.waitForTimeout(100); // drawn on the next frame
    const after = await canvasPixels(page);
    // Green but the walls (along which the grids differ, a cell's verdict colours the wall it tops).
    if (after.within - before.within < 0.3 * before.drawn) {
      fail(`the design layer turned ${after.within - before.within} of the ${before.drawn} pixels drawn green`);
    }
    await page.keyboard.press('d');
  });

  // A feed move long enough to see: its output line, and the program line it came from.
  const feed = pieces.find((p) => p.kind === 1 && Math.hypot(p.x1 - p.x0, p.y1 - p.y0) > 5);
  if (!feed) fail('the example has no feed move 5 units long');
  const line = feed.line;
  const sourceLine = state.output.source_lines[line];

  await step(`clicking output line ${line + 1} highlights its move and program line ${sourceLine}`, async () => {
    // Scroll the translation to the line like a user would, then click it.
    await page.locator('#output').evaluate((e, l) => (e.scrollTop = Math.max(0, l * 18 - 100)), line);
    const row = page.locator(`#output .vrow[data-i="${line}"]`);
    await row.click();
    await page.waitForFunction(
      (l) => document.querySelector(`#output .vrow.sel`)?.dataset.i === String(l),
      line,
      { timeout: 5000 },
    );
    await page.waitForTimeout(100); // the highlight is drawn on the next frame
    const { highlight } = await canvasPixels(page);
    if (highlight < 20) fail(`the view shows ${highlight} pixels of the selection's colour`);
    const marked = await page.locator('#editor .gutter .sel').textContent();
    if (marked !== String(sourceLine)) fail(`the program pane marks line ${marked}, not ${sourceLine}`);
    if (!(await page.locator(`#editor .backdrop .hl[data-line="${sourceLine}"]`).count())) {
      fail(`the program pane does not highlight line ${sourceLine}`);
    }
    // The status says when the planned run gets there, of how long in all.
    const runTime = await page.locator('#runTime').textContent();
    if (!/^reaches line \d+ at [\d.]+ s|^reaches line \d+ at \d+ min \d\d s/.test(runTime) || !runTime.startsWith(`reaches line ${sourceLine} `)) {
      fail(`the status says "${runTime}", not when the run reaches line ${sourceLine}`);
    }
    if (!runTime.includes('planned (grbl-default')) fail(`the status says "${runTime}", not the planned time and its profile`);
  });

  await step('clicking a move in the 3D view selects its output line', async () => {
    const box = await page.locator('#view').boundingBox();
    // Project every piece as the page does; pick one whose middle is clear of
    // the others' lines, so which one the click means is not in doubt.
    const target = await page.evaluate(
      ({ pieces, exclude }) => {
        const on = pieces.map((p) => [window.gerView.project([p.x0, p.y0, p.z0]), window.gerView.project([p.x1, p.y1, p.z1]), p]);
        const distance = ([a, b], x, y) => {
          const dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
          const t = l2 ? Math.max(0, Math.min(1, ((x - a[0]) * dx + (y - a[1]) * dy) / l2)) : 0;
          return Math.hypot(a[0] + t * dx - x, a[1] + t * dy - y);
        };
        for (const s of on) {
          const [a, b, p] = s;
          if (!a || !b || p.line === exclude || Math.hypot(b[0] - a[0], b[1] - a[1]) < 30) continue;
          const x = (a[0] + b[0]) / 2, y = (a[1] + b[1]) / 2;
          const near = on.filter((o) => o[0] && o[1] && distance(o, x, y) <= 6).map((o) => o[2].line);
          if (near.every((l) => l === p.line)) return { x, y, line: p.line };
        }
        return null;
      },
      { pieces, exclude: line },
    );
    if (!target) fail('no move stands clear enough on screen to click');
    await page.mouse.click(box.x + target.x, box.y + target.y);
    await page.waitForFunction(
      (l) => document.querySelector(`#output .vrow.sel`)?.dataset.i === String(l),
      target.line,
      { timeout: 5000 },
    ).catch(() => fail(`clicking the move of output line ${target.line + 1} did not select it`));
  });

  // Change a coordinate of a move in the program text: the translation follows.
  const lines = state.source.split('\n');
  const edited = lines.findIndex((l) => /^G0?0 X[\d.]+/.test(l) && !/\(/.test(l));
  if (edited < 0) fail('the example has no "G00 X…" line to edit');
  const oldX = lines[edited].match(/X([\d.]+)/)[1];
  const newX = String(Number(oldX) + 7.25);

  await step(`typing X${newX} for X${oldX} on program line ${edited + 1} changes the translation`, async () => {
    const before = Number(await page.evaluate(() => document.body.dataset.shown));
    const textarea = page.locator('#sourceText');
    await textarea.click();
    // Select the number like a double-click would, then type over it.
    await textarea.evaluate(
      (t, { line, oldX }) => {
        const start = t.value.split('\n').slice(0, line).join('\n').length + (line ? 1 : 0);
        const at = start + t.value.slice(start).indexOf(`X${oldX}`) + 1;
        t.setSelectionRange(at, at + oldX.length);
      },
      { line: edited, oldX },
    );
    await page.keyboard.type(newX, { delay: 20 });
    await waitShown(page, before + 1);
    await page.keyboard.press('End'); // the caret's line is selected; its output rows are marked
    await page.waitForFunction(
      (x) => [...document.querySelectorAll('#output .vrow.related .text, #output .vrow.sel .text')].some((e) => e.textContent.includes(`X${x}`)),
      newX,
      { timeout: 5000 },
    ).catch(() => fail(`no output line of program line ${edited + 1} shows X${newX}`));
  });

  if (program) {
    await step('Ctrl-S saves the edit to the file', async () => {
      await page.keyboard.press('Control+s');
      const deadline = Date.now() + 5000;
      while (!fs.readFileSync(program, 'utf8').includes(`X${newX}`)) {
        if (Date.now() > deadline) fail(`${program} does not have the edit 5 s after Ctrl-S`);
        await new Promise((r) => setTimeout(r, 50));
      }
      await page.waitForFunction(() => document.getElementById('saved').textContent === 'saved', null, { timeout: 5000 });
    });
  }

  await step(`a screenshot goes to ${screenshot}`, async () => {
    // The feed move selected again: the picture shows a highlight on the part.
    await page.locator('#output').evaluate((e, l) => (e.scrollTop = Math.max(0, l * 18 - 100)), line);
    await page.locator(`#output .vrow[data-i="${line}"]`).click();
    await page.waitForTimeout(200);
    await page.screenshot({ path: screenshot });
  });

  if (errors.length) fail(`the page reported errors:\n${errors.join('\n')}`);
  console.log('view.mjs: all checks passed');
} finally {
  await browser.close();
}

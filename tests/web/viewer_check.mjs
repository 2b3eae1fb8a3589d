// Drives the live viewer in headless Chromium (Debian's /usr/bin/chromium, through playwright-core
// from the page's npm packages): opens PAGES pages on one scene while it builds, waits until each
// has drawn what the daemon holds, asks one page for a tour, takes a screenshot, and prints one
// JSON object. Usage:
//   node viewer_check.mjs URL SCENE PAGES SCREENSHOT.png TIMEOUT_S [--close-one-early] [--ready-file=PATH]
// With --ready-file, PATH is written once every page is open (the test then starts the build).
// ISPARS_WEB_NODE_MODULES names the node_modules holding playwright-core.
import { writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(process.env.ISPARS_WEB_NODE_MODULES + '/');
const { chromium } = require('playwright-core');

const [url, scene, pagesArg, screenshot, timeoutArg, ...flags] = process.argv.slice(2);
const pageCount = Number(pagesArg);
const deadline = Date.now() + Number(timeoutArg) * 1000;
const closeOneEarly = flags.includes('--close-one-early');
// --wait-text=ID:TEXT: one page, until its element ID contains TEXT; prints that element's text.
// TEXT 'drawn' waits instead until the page has drawn all the daemon's roadmap.
const waitText = (flags.find((f) => f.startsWith('--wait-text=')) || '').slice('--wait-text='.length);
// --task=NAME: one page, until it lists task NAME; chooses it, then asks for a tour; prints what
// the page drew of the task and the tour.
const taskName = (flags.find((f) => f.startsWith('--task=')) || '').slice('--task='.length);
const readyFile = (flags.find((f) => f.startsWith('--ready-file=')) || '').slice('--ready-file='.length);

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
         '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const result = { pages: [], console_errors: [] };
let context = null;
try {
  context = await browser.newContext({ viewport: { width: 1000, height: 700 } });
  context.setDefaultNavigationTimeout(120000);  // a loaded CI machine: four pages draw in software
  const open = async () => {
    const page = await context.newPage();
    page.on('pageerror', (e) => result.console_errors.push(String(e)));
    await page.goto(`${url}?scene=${encodeURIComponent(scene)}`);
    return page;
  };
  if (waitText) {
    const [id, text] = [waitText.slice(0, waitText.indexOf(':')), waitText.slice(waitText.indexOf(':') + 1)];
    const page = await open();
    // The element's text, and with 'drawn' the page's whole roadmap too (the daemon idle, and
    // every vertex and edge of its status drawn).
    await page.waitForFunction(([i, t]) => {
      const v = window.viewer;
      const drawn = t !== 'drawn' || (v.status && v.status.state === 'idle' && v.vertices === v.status.vertices &&
                                      v.edges === v.status.edges && v.vertices > 0);
      return t === 'drawn' ? drawn : document.getElementById(i).textContent.includes(t);
    }, [id, text], { timeout: Number(timeoutArg) * 1000, polling: 100 });
    await page.waitForTimeout(1000);  // anything more that would arrive
    result.text = await page.evaluate((i) => document.getElementById(i).textContent, id);
    result.vertices = await page.evaluate(() => window.viewer.vertices);
    result.edges = await page.evaluate(() => window.viewer.edges);
    result.errors = await page.evaluate(() => window.viewer.errors);
    await browser.close();
    console.log(JSON.stringify(result));
    process.exit(0);
  }
  if (taskName) {
    const page = await open();
    const timeout = Number(timeoutArg) * 1000;
    await page.waitForFunction((t) => [...document.querySelectorAll('#task option')].some((o) => o.value === t),
                               taskName, { timeout, polling: 100 });
    await page.selectOption('#task', taskName);
    await page.waitForFunction(() => window.viewer.task_pois > 0, null, { timeout, polling: 100 });
    await page.click('#tour_button');
    await page.waitForFunction(() => window.viewer.tour !== null, null, { timeout, polling: 100 });
    Object.assign(result, await page.evaluate(() => ({
      task_pois: window.viewer.task_pois, task_info: document.getElementById('task_info').textContent,
      tasks: window.viewer.tasks.map((t) => ({ name: t.name, poi_count: t.poi_count, root: t.pois_covered_root })),
      tour: { task: window.viewer.tour.task, targets: window.viewer.tour.targets, covered: window.viewer.tour.covered,
              valid: window.viewer.tour.valid, text: document.getElementById('tour').textContent },
      errors: window.viewer.errors,
    })));
    await browser.close();
    console.log(JSON.stringify(result));
    process.exit(0);
  }
  const pages = [];
  for (let i = 0; i < pageCount; i++) pages.push(await open());
  const early = closeOneEarly ? await open() : null;
  if (readyFile) writeFileSync(readyFile, 'open\n');
  if (early) {
    // A browser that goes away mid-stream: the gateway must go on serving the others.
    await early.waitForFunction(() => window.viewer && window.viewer.batches > 0, null, { timeout: 60000 });
    await early.close();
    result.closed_early = true;
  }
  // Each page is done when the daemon is idle and the page has drawn every vertex and edge of its
  // status (which the test then compares with `ispars stats`).
  for (const page of pages) {
    const start = Date.now();
    await page.waitForFunction(() => {
      const v = window.viewer;
      return v && v.status && v.status.state === 'idle' && v.vertices === v.status.vertices &&
          v.edges === v.status.edges && v.vertices > 0;
    }, null, { timeout: Math.max(1000, deadline - Date.now()), polling: 100 });
    const state = await page.evaluate(() => ({
      vertices: window.viewer.vertices, edges: window.viewer.edges, batches: window.viewer.batches,
      frames: window.viewer.frames, mesh: window.viewer.mesh, errors: window.viewer.errors,
      shown_vertices: Number(document.getElementById('vertices').textContent),
      shown_edges: Number(document.getElementById('edges').textContent),
    }));
    state.waited_ms = Date.now() - start;
    state.caught_up_at = new Date().toISOString();
    result.pages.push(state);
  }
  // The drawing: pixels of the WebGL canvas that are not the background.
  const page = pages[0];
  await page.waitForTimeout(300);
  result.drawn_pixels = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const d = ctx.getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - 0xe8) + Math.abs(d[i + 1] - 0xee) + Math.abs(d[i + 2] - 0xf6) > 30) n++;
    }
    return { drawn: n, total: c.width * c.height };
  });
  await page.screenshot({ path: screenshot });
  // A tour on request.
  await page.click('#tour_button');
  await page.waitForFunction(() => window.viewer.tour !== null, null, { timeout: 60000 });
  result.tour = await page.evaluate(() => ({ cost: window.viewer.tour.cost, waypoints: window.viewer.tour.positions.length,
                                              valid: window.viewer.tour.valid, text: document.getElementById('tour').textContent }));
  // An unknown scene: a clear message, and the gateway keeps serving.
  const unknown = await context.newPage();
  await unknown.goto(`${url}?scene=no_such_scene`);
  await unknown.waitForFunction(() => window.viewer && window.viewer.errors.length > 0, null, { timeout: 60000 });
  result.unknown_scene_error = await unknown.evaluate(() => window.viewer.errors[0]);
} catch (e) {
  result.failure = String(e);
  // What the pages showed when it failed: the viewer's state and its note.
  result.seen = [];
  for (const page of context ? context.pages() : []) {
    result.seen.push(await page.evaluate(() => ({
      url: location.href, note: (document.getElementById('note') || {}).textContent,
      daemon_note: (document.getElementById('daemon_note') || {}).textContent,
      viewer: window.viewer ? { vertices: window.viewer.vertices, edges: window.viewer.edges, batches: window.viewer.batches,
                                status: window.viewer.status, errors: window.viewer.errors, mesh: window.viewer.mesh } : null,
    })).catch((err) => String(err)));
  }
} finally {
  await browser.close();
}
console.log(JSON.stringify(result));

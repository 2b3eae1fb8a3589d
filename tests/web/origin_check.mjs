// A page of another origin tries the gateway, in headless Chromium (Debian's /usr/bin/chromium,
// through playwright-core from the page's npm packages): this script serves a page on
// http://127.0.0.1:PAGE_PORT/ whose script opens ws://127.0.0.1:GATEWAY_PORT/ws?scene=SCENE, as
// any page open in the user's browser could. Prints one JSON object: whether the WebSocket opened
// ("open") or was refused ("refused", with its close code), and the Origin the page had. Usage:
//   node origin_check.mjs GATEWAY_PORT PAGE_PORT SCENE TIMEOUT_S
// ISPARS_WEB_NODE_MODULES names the node_modules holding playwright-core.
import { createServer } from 'node:http';
import { createRequire } from 'node:module';

const require = createRequire(process.env.ISPARS_WEB_NODE_MODULES + '/');
const { chromium } = require('playwright-core');

const [gatewayPort, pagePort, scene, timeoutArg] = process.argv.slice(2);
const page = `<!doctype html><title>another origin</title><script>
window.result = null;
const ws = new WebSocket('ws://127.0.0.1:${gatewayPort}/ws?scene=${encodeURIComponent(scene)}');
ws.onopen = () => { window.result = { ws: 'open', origin: location.origin }; ws.close(); };
ws.onclose = (e) => { if (!window.result) window.result = { ws: 'refused', code: e.code, origin: location.origin }; };
</script>`;
const server = createServer((request, response) => {
  response.writeHead(200, { 'content-type': 'text/html; charset=utf-8' });
  response.end(page);
});
await new Promise((resolve) => server.listen(Number(pagePort), '127.0.0.1', resolve));

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync'],
});
let result = {};
try {
  const tab = await browser.newPage();
  await tab.goto(`http://127.0.0.1:${pagePort}/`);
  await tab.waitForFunction(() => window.result !== null, null, { timeout: Number(timeoutArg) * 1000, polling: 100 });
  result = await tab.evaluate(() => window.result);
} catch (e) {
  result.failure = String(e);
} finally {
  await browser.close();
  server.close();
}
console.log(JSON.stringify(result));

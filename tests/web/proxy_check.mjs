// The gateway as users reach it through a TLS proxy (nginx, self-signed certificate): each mode
// prints one JSON object. Usage:
//   node proxy_check.mjs follow BASE TOKEN SCENE TIMEOUT_S READY_FILE
//     headless Chromium opens BASE/?token=TOKEN (the cookie), then the scene's page; once
//     READY_FILE is written the test starts a build, which the page follows to its end over wss.
//   node proxy_check.mjs ask BASE TOKEN       a page without the token, with it, and a WebSocket
//   node proxy_check.mjs flood BASE TOKEN N   a WebSocket that sends N requests of 60 kB and never
//                                             reads; waits (at most 120 s) for the far side to close it
//   node proxy_check.mjs idle BASE TOKEN N    N TLS connections that send nothing, held while
//                                             another user asks for the page and over a WebSocket
// BASE is https://HOST:PORT. ISPARS_WEB_NODE_MODULES names the node_modules holding playwright-core.
import { writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import https from 'node:https';
import tls from 'node:tls';

const [mode, base, token, ...rest] = process.argv.slice(2);
const url = new URL(base);
const tlsOptions = { host: url.hostname, port: Number(url.port), servername: url.hostname, rejectUnauthorized: false };

// One GET through the proxy: its status.
function get(path, headers = {}) {
  return new Promise((resolve) => {
    const request = https.get({ ...tlsOptions, path, headers, timeout: 20000 }, (response) => {
      response.resume();
      response.on('end', () => resolve(response.statusCode));
    });
    request.on('timeout', () => request.destroy(new Error('timed out')));
    request.on('error', (e) => resolve(String(e)));
  });
}

// A WebSocket over TLS (RFC 6455, a few lines): the upgrade's status line, then masked text
// frames out and the first text frame in.
function webSocket(path, headers) {
  return new Promise((resolve) => {
    const socket = tls.connect(tlsOptions);
    let buffer = Buffer.alloc(0);
    let status = null;
    const waiting = [];
    socket.on('data', (chunk) => {
      buffer = Buffer.concat([buffer, chunk]);
      if (status === null) {
        const end = buffer.indexOf('\r\n\r\n');
        if (end < 0) return;
        status = buffer.subarray(0, buffer.indexOf('\r\n')).toString();
        buffer = buffer.subarray(end + 4);
        resolve(ws);
      }
      while (buffer.length >= 2) {
        let length = buffer[1] & 0x7f;
        let head = 2;
        if (length === 126) { length = buffer.readUInt16BE(2); head = 4; }
        if (length === 127) { length = Number(buffer.readBigUInt64BE(2)); head = 10; }
        if (buffer.length < head + length) return;
        const opcode = buffer[0] & 0x0f;
        const text = buffer.subarray(head, head + length).toString();
        buffer = buffer.subarray(head + length);
        if (opcode === 1 && waiting.length > 0) waiting.shift()(text);
      }
    });
    socket.on('error', () => {});
    socket.on('close', () => { if (status === null) resolve(ws); while (waiting.length) waiting.shift()(null); });
    const ws = {
      socket,
      status: () => status,
      send(text) {
        const payload = Buffer.from(text);
        const head = payload.length < 126 ? Buffer.from([0x81, 0x80 | payload.length])
          : Buffer.from([0x81, 0x80 | 126, payload.length >> 8, payload.length & 0xff]);
        const mask = Buffer.from([0x11, 0x22, 0x33, 0x44]);
        for (let i = 0; i < payload.length; i++) payload[i] ^= mask[i % 4];
        return socket.write(Buffer.concat([head, mask, payload]));
      },
      next: (ms) => new Promise((done) => { waiting.push(done); setTimeout(() => done(null), ms); }),
    };
    const lines = Object.entries(headers).map(([k, v]) => `${k}: ${v}\r\n`).join('');
    socket.write(`GET ${path} HTTP/1.1\r\nHost: ${url.host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n` +
                 `Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n${lines}\r\n`);
  });
}

// A user asks over a WebSocket and is answered: the time it took, or null.
async function answered(headers) {
  const start = Date.now();
  const ws = await webSocket('/ws?scene=s0', headers);
  if (!(ws.status() || '').includes(' 101 ')) return { status: ws.status(), answered_ms: null };
  ws.send('{"type":"nonsense"}');
  let reply = await ws.next(20000);
  while (reply !== null && !reply.includes('is not tour or tasks')) reply = await ws.next(20000);
  ws.socket.destroy();
  return { status: ws.status(), answered_ms: reply === null ? null : Date.now() - start };
}

const bearer = { Authorization: `Bearer ${token}` };

async function follow(scene, timeoutS, readyFile) {
  const require = createRequire(process.env.ISPARS_WEB_NODE_MODULES + '/');
  const { chromium } = require('playwright-core');
  const browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const result = { sockets: [], console_errors: [] };
  try {
    const context = await browser.newContext({ ignoreHTTPSErrors: true, viewport: { width: 800, height: 600 } });
    context.setDefaultNavigationTimeout(120000);
    const page = await context.newPage();
    page.on('pageerror', (e) => result.console_errors.push(String(e)));
    page.on('websocket', (ws) => result.sockets.push(ws.url()));
    result.with_token = (await page.goto(`${base}/?token=${token}`)).status();
    result.cookies = (await context.cookies()).map((c) => ({ name: c.name, secure: c.secure, httpOnly: c.httpOnly }));
    await page.goto(`${base}/?scene=${encodeURIComponent(scene)}`);
    await page.waitForFunction(() => window.viewer && window.viewer.status, null, { timeout: 60000, polling: 100 });
    writeFileSync(readyFile, 'open\n');
    await page.waitForFunction(() => {
      const v = window.viewer;
      return v.status.state === 'idle' && v.batches > 0 && v.vertices === v.status.vertices &&
          v.edges === v.status.edges && v.vertices > 0;
    }, null, { timeout: Number(timeoutS) * 1000, polling: 100 });
    Object.assign(result, await page.evaluate(() => ({
      vertices: window.viewer.vertices, edges: window.viewer.edges, batches: window.viewer.batches,
      samples: window.viewer.status.samples_done, errors: window.viewer.errors })));
  } catch (e) {
    result.failure = String(e);
  } finally {
    await browser.close();
  }
  return result;
}

async function flood(count) {
  const ws = await webSocket('/ws?scene=s0', bearer);
  const result = { status: ws.status(), sent: 0, closed: false };
  ws.socket.pause();  // never reads: what the gateway sends piles up behind nginx and the kernel
  const closed = new Promise((done) => ws.socket.on('close', () => done(true)));
  const request = `{"type":"${'x'.repeat(60000)}"}`;
  for (let i = 0; i < count && !ws.socket.destroyed; i++) {
    if (!ws.send(request)) await Promise.race([new Promise((d) => ws.socket.once('drain', d)), closed]);
    result.sent = i + 1;
  }
  result.closed = await Promise.race([closed, new Promise((d) => setTimeout(() => d(false), 120000))]);
  ws.socket.destroy();
  return result;
}

async function idle(count) {
  const held = [];
  for (let i = 0; i < count; i++) {
    held.push(await new Promise((done) => {
      const s = tls.connect(tlsOptions, () => done(s));
      s.on('error', () => done(s));
    }));
  }
  const result = { held: held.filter((s) => !s.destroyed).length };
  result.page = await get('/', bearer);
  Object.assign(result, await answered(bearer));
  result.still_held = held.filter((s) => !s.destroyed).length;
  for (const s of held) s.destroy();
  return result;
}

let result;
if (mode === 'follow') {
  result = await follow(rest[0], rest[1], rest[2]);
} else if (mode === 'ask') {
  result = { without_token: await get('/'), with_token: await get('/', bearer),
             wrong_token: await get('/', { Authorization: 'Bearer wrong-token-0123456789' }),
             ws_without_token: (await webSocket('/ws?scene=s0', {})).status(), ...(await answered(bearer)) };
} else if (mode === 'flood') {
  result = await flood(Number(rest[0]));
} else if (mode === 'idle') {
  result = await idle(Number(rest[0]));
} else {
  result = { failure: `unknown mode '${mode}'` };
}
console.log(JSON.stringify(result));
process.exit(0);

// A Foxglove WebSocket client (@foxglove/ws-protocol's, over the ws package) against ispars-web:
// subscribes to the advertised roadmap channel, checks every message against @foxglove/schemas'
// foxglove.SceneUpdate with ajv, replays them (deletions, then entities by id), and ends once the
// replay holds VERTICES spheres and EDGES line-list edges, or after SECONDS.
// Usage: node foxglove_client.cjs URL VERTICES EDGES SECONDS. Prints one JSON object.
"use strict";
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const { SceneUpdate } = require("@foxglove/schemas/jsonschema");
const Ajv = require("ajv");

const [url, vertices, edges, seconds] = process.argv.slice(2);
const validate = new Ajv({ strict: false }).compile(SceneUpdate);
const scene = new Map();
const out = { server: null, channels: [], messages: 0, invalid: 0, statuses: [], spheres: 0, edges: 0, done: false };
const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });

function finish(code) {
  process.stdout.write(JSON.stringify(out) + "\n");
  client.close();
  process.exit(code);
}
client.on("serverInfo", (info) => (out.server = info.name));
client.on("status", (s) => out.statuses.push(s.message));
client.on("error", (e) => out.statuses.push(`client error: ${e}`));
client.on("advertise", (channels) => {
  for (const c of channels) {
    out.channels.push({ topic: c.topic, schemaName: c.schemaName, schemaEncoding: c.schemaEncoding });
    client.subscribe(c.id);
  }
  // A bad request is answered with a status naming it; the session goes on.
  ws.send(JSON.stringify({ op: "publish" }));
});
client.on("message", ({ data }) => {
  const update = JSON.parse(new TextDecoder().decode(data));
  out.messages += 1;
  if (!validate(update)) out.invalid += 1;
  for (const d of update.deletions) if (d.type === 1) scene.clear(); else scene.delete(d.id);
  for (const e of update.entities) scene.set(e.id, e);
  out.spheres = 0;
  out.edges = 0;
  for (const e of scene.values()) {
    out.spheres += e.spheres.length;
    for (const l of e.lines) if (l.type === 2) out.edges += l.points.length / 2;
  }
  if (out.spheres === Number(vertices) && out.edges === Number(edges) && out.statuses.length > 0) {
    out.done = true;
    finish(0);
  }
});
setTimeout(() => finish(1), Number(seconds) * 1000);

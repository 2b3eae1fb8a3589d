// Reads an MCAP file `ispars record` wrote, with @mcap/core's readers (the streaming one, record by
// record, and the indexed one, through the summary and chunk indexes as Foxglove seeks), checks
// every message against the foxglove.SceneUpdate JSON Schema of @foxglove/schemas with ajv, and
// replays the scene: deletions, then entities replacing those of the same id.
// Usage: node check_mcap.cjs FILE. Prints one JSON object: what the replay holds, per topic.
"use strict";
const fs = require("fs");
const { McapStreamReader, McapIndexedReader } = require("@mcap/core");
const { SceneUpdate } = require("@foxglove/schemas/jsonschema");
const Ajv = require("ajv");

const bytes = new Uint8Array(fs.readFileSync(process.argv[2]));
const validate = new Ajv({ strict: false, allErrors: true }).compile(SceneUpdate);
const schemas = new Map();
const channels = new Map();
const scenes = new Map();  // topic -> Map(entity id -> entity)
const summary = { messages: 0, invalid: [], schema_names: [], topics: {} };

function apply(topic, update) {
  if (!scenes.has(topic)) scenes.set(topic, new Map());
  const scene = scenes.get(topic);
  for (const d of update.deletions) {
    if (d.type === 1) scene.clear();
    else scene.delete(d.id);
  }
  for (const e of update.entities) scene.set(e.id, e);
}

const reader = new McapStreamReader({ validateCrcs: true });
reader.append(bytes);
for (let record; (record = reader.nextRecord()); ) {
  if (record.type === "Schema") schemas.set(record.id, record);
  if (record.type === "Channel") channels.set(record.id, record);
  if (record.type !== "Message") continue;
  const channel = channels.get(record.channelId);
  const schema = schemas.get(channel.schemaId);
  const update = JSON.parse(new TextDecoder().decode(record.data));
  if (!validate(update)) summary.invalid.push({ topic: channel.topic, errors: validate.errors.slice(0, 3) });
  if (!summary.schema_names.includes(schema.name)) summary.schema_names.push(schema.name);
  apply(channel.topic, update);
  summary.messages += 1;
}
if (!reader.done()) throw new Error("the stream reader did not reach the end of the file");

for (const [topic, scene] of scenes) {
  let spheres = 0, lineLists = 0, strips = [];
  for (const e of scene.values()) {
    spheres += e.spheres.length;
    for (const l of e.lines) {
      if (l.type === 2) lineLists += l.points.length / 2;
      if (l.type === 0) strips.push(l.points.map((p) => [p.x, p.y, p.z]));
    }
  }
  summary.topics[topic] = { entities: scene.size, spheres, edges: lineLists, strips };
}

(async () => {
  const indexed = await McapIndexedReader.Initialize({
    readable: { size: async () => BigInt(bytes.length), read: async (o, n) => bytes.slice(Number(o), Number(o + n)) },
  });
  let count = 0;
  for await (const _ of indexed.readMessages()) count += 1;
  summary.indexed_messages = count;
  summary.statistics_messages = indexed.statistics ? Number(indexed.statistics.messageCount) : -1;
  process.stdout.write(JSON.stringify(summary) + "\n");
})().catch((e) => {
  console.error(e);
  process.exit(1);
});

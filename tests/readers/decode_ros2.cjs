// Decodes one serialized ROS 2 sample with Foxglove's ROS 2 CDR reader and the ROS 2 message
// definitions of @foxglove/rosmsg-msgs-common (Jazzy's; Humble's fields are checked to agree: the
// two differ only in a constant, Jazzy's ARROW_STRIP), never with
// ispars's own IDL: what a ROS 2 viewer would make of isparsd --ros2's bytes.
// Usage: node decode_ros2.cjs TYPE FILE   (TYPE: visualization_msgs/MarkerArray or nav_msgs/Path)
// Prints one JSON object: the message, with numbers as decoded.
"use strict";
const fs = require("fs");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const common = require("@foxglove/rosmsg-msgs-common");

// The root type's definition, then every type it names, transitively (the reader's input).
function definitionsOf(library, root) {
  const out = [];
  const seen = new Set();
  const visit = (name) => {
    if (seen.has(name)) return;
    seen.add(name);
    const def = library[name];
    if (!def) throw new Error(`no definition of ${name}`);
    out.push(def);
    for (const field of def.definitions) {
      if (!field.isConstant && field.isComplex) visit(field.type);
    }
  };
  visit(root);
  return out;
}

const [type, file] = process.argv.slice(2);
const jazzy = definitionsOf(common.ros2jazzy, type);
const humble = definitionsOf(common.ros2humble, type);
const layout = (defs) => JSON.stringify(defs.map((d) => [d.name, d.definitions.filter((f) => !f.isConstant)]));
if (layout(jazzy) !== layout(humble)) throw new Error(`Humble and Jazzy lay ${type} out apart`);
const bytes = fs.readFileSync(file);
const message = new MessageReader(jazzy).readMessage(bytes);
const plain = (value) => {
  if (ArrayBuffer.isView(value)) return Array.from(value);
  if (typeof value === "bigint") return Number(value);
  return value;
};
process.stdout.write(JSON.stringify(message, (key, value) => plain(value)) + "\n");

// Reads an MCAP file written by rigid-record export --mcap with independent code (@mcap/core's
// indexed reader, protobufjs) and checks it against the recording it came from, given as
// rigid-record export --csv's rows (17 significant digits: every double round-trips exactly).
//
//   node check_mcap.mjs OUT.mcap REFERENCE.csv STATES BODIES COMPRESSION
//
// COMPRESSION: what every chunk must say it is ("zstd", or "none" for MCAP's ""). zstd chunks are
// decompressed with fzstd (an independent zstd decoder in JavaScript), as a Foxglove-side reader
// would with its own.
//
// Exit status 0: every check passed; 1: a check failed (the first failure is printed).
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { crc32 } from "@foxglove/crc";
import { decompress } from "fzstd";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor/index.js";
import { open, readFile } from "node:fs/promises";

const [mcapPath, csvPath, statesArg, bodiesArg, compressionArg] = process.argv.slice(2);
const expectedCompression = compressionArg === "none" ? "" : compressionArg;
const expectedStates = Number(statesArg);
const expectedBodies = Number(bodiesArg);

function check(ok, what) {
  if (!ok) {
    console.error(`check_mcap: FAILED: ${what}`);
    process.exit(1);
  }
}

// The reference: per state (in file order), per body, [name, x, y, z, qw, qx, qy, qz].
const rows = (await readFile(csvPath, "utf8")).trim().split("\n").slice(1);
const reference = [];
let lastT;
for (const row of rows) {
  const c = row.split(",");
  if (c[0] !== lastT) {
    reference.push([]);
    lastT = c[0];
  }
  reference[reference.length - 1].push([c[1], ...c.slice(2, 9).map(Number)]);
}
check(reference.length === expectedStates, `the CSV holds ${reference.length} states, not ${expectedStates}`);

const handle = await open(mcapPath, "r");
const size = (await handle.stat()).size;
const readable = {
  size: async () => BigInt(size),
  read: async (offset, length) => {
    const buffer = new Uint8Array(Number(length));
    const { bytesRead } = await handle.read(buffer, 0, Number(length), Number(offset));
    check(bytesRead === Number(length), `short read at ${offset}`);
    return buffer;
  },
};

// zstd chunks: decompressed to the size the chunk states (the readers then check its CRC).
let decompressed = 0;
const decompressHandlers = {
  zstd: (buffer, size) => {
    const out = decompress(buffer);
    check(BigInt(out.length) === size, `a zstd chunk of ${out.length} bytes, not ${size}`);
    ++decompressed;
    return out;
  },
};

// Initialize reads the footer, the summary offsets and the summary, and checks the summary CRC.
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
check(reader.chunkIndexes.length > 0, "no chunk indexes");
for (const c of reader.chunkIndexes) {
  check(c.compression === expectedCompression, `a chunk compressed '${c.compression}'`);
  if (c.compression === "") check(c.compressedSize === c.uncompressedSize, "an uncompressed chunk's sizes differ");
  else check(c.compressedSize < c.uncompressedSize, "a compressed chunk no smaller than its records");
}
check(reader.statistics !== undefined, "no Statistics record");
check(reader.footer.summaryCrc !== 0, "no summary CRC");
check(reader.dataSectionCrc !== undefined && reader.dataSectionCrc !== 0, "no data section CRC");

// The data section CRC: every byte from the start of the file to the DataEnd record (13 bytes:
// opcode, length, crc), which ends where the summary starts.
const whole = await readFile(mcapPath);
const dataEnd = Number(reader.footer.summaryStart) - 13;
check(whole[dataEnd] === 0x0f, "no DataEnd record just before the summary");
check(crc32(whole.subarray(0, dataEnd)) === reader.dataSectionCrc, "data section CRC differs");

// The stream reader walks every record from the start, checking chunk CRCs and the record
// structure the index does not cover (message indexes, DataEnd, summary offsets, footer).
{
  const stream = new McapStreamReader({ validateCrcs: true, decompressHandlers });
  stream.append(whole);
  let records = 0;
  let messageIndexes = 0;
  for (let r; (r = stream.nextRecord()); ) {
    ++records;
    if (r.type === "MessageIndex") ++messageIndexes;
  }
  check(stream.done(), "the stream reader did not reach the end magic");
  check(messageIndexes > 0, "no MessageIndex records");
}

// Schemas: protobuf, a FileDescriptorSet each; every channel's messages decode against it.
const types = new Map();
for (const schema of reader.schemasById.values()) {
  check(schema.encoding === "protobuf", `schema ${schema.name}: encoding ${schema.encoding}`);
  const set = descriptor.FileDescriptorSet.decode(schema.data);
  const root = protobuf.Root.fromDescriptor(set);
  types.set(schema.id, root.lookupType(schema.name));
}
const topics = new Map();
for (const channel of reader.channelsById.values()) {
  check(channel.messageEncoding === "protobuf", `channel ${channel.topic}: ${channel.messageEncoding}`);
  check(types.has(channel.schemaId), `channel ${channel.topic}: no schema`);
  topics.set(channel.id, channel.topic);
}
const schemaName = (topic) => {
  for (const c of reader.channelsById.values()) if (c.topic === topic) return reader.schemasById.get(c.schemaId).name;
};
check(schemaName("/rigid/transforms") === "foxglove.FrameTransforms", "transforms schema name");
check(schemaName("/rigid/bodies") === "foxglove.SceneUpdate", "bodies schema name");
check(schemaName("/rigid/state") === "rigid.msgs.StateRecord", "state schema name");

const same = (a, b) => Object.is(a, b);  // bit for bit for doubles (-0 is not 0; no NaN here)
const counts = new Map();
let transformsSeen = 0;
let statesSeen = 0;
let updates = 0;
let lastLogTime = -1n;
for await (const m of reader.readMessages()) {  // chunk CRCs validated (the default)
  const topic = topics.get(m.channelId);
  counts.set(topic, (counts.get(topic) ?? 0) + 1);
  check(m.logTime >= lastLogTime, `${topic}: log times out of order`);
  lastLogTime = m.logTime;
  const type = types.get(reader.channelsById.get(m.channelId).schemaId);
  const err = type.verify(type.decode(m.data));
  check(err === null, `${topic}: ${err}`);
  const msg = type.toObject(type.decode(m.data), { longs: String, defaults: true });
  if (topic === "/rigid/transforms") {
    const ref = reference[transformsSeen++];
    check(ref !== undefined, "more transforms messages than states");
    check(msg.transforms.length === ref.length, "a transforms message with another body count");
    const stampNs = BigInt(msg.transforms[0].timestamp.seconds) * 1000000000n + BigInt(msg.transforms[0].timestamp.nanos);
    check(stampNs === m.logTime, "a transform's timestamp is not its message's log_time");
    msg.transforms.forEach((t, i) => {
      const [name, x, y, z, qw, qx, qy, qz] = ref[i];
      check(t.parent_frame_id === "world" && t.child_frame_id === name, `frames ${t.parent_frame_id} -> ${t.child_frame_id}`);
      const tr = t.translation;
      const q = t.rotation;
      check(same(tr.x, x) && same(tr.y, y) && same(tr.z, z), `state ${transformsSeen}: ${name} translation ${tr.x},${tr.y},${tr.z} != ${x},${y},${z}`);
      check(same(q.w, qw) && same(q.x, qx) && same(q.y, qy) && same(q.z, qz), `state ${transformsSeen}: ${name} rotation`);
    });
  } else if (topic === "/rigid/state") {
    const ref = reference[statesSeen++];
    check(msg.ids.length === ref.length, "a state with another body count");
    ref.forEach(([, x, y, z, qw, qx, qy, qz], i) => {
      const p = msg.position.slice(3 * i, 3 * i + 3);
      const q = msg.orientation.slice(4 * i, 4 * i + 4);
      check(same(p[0], x) && same(p[1], y) && same(p[2], z), `state ${statesSeen}: position of body ${i}`);
      check(same(q[0], qw) && same(q[1], qx) && same(q[2], qy) && same(q[3], qz), `state ${statesSeen}: orientation`);
    });
  } else if (topic === "/rigid/bodies") {
    ++updates;
    check(msg.entities.length === expectedBodies, `a SceneUpdate of ${msg.entities.length} entities`);
    for (const e of msg.entities) {
      check(e.frame_id === e.id && e.frame_locked, `entity ${e.id}: frame ${e.frame_id}`);
      const primitives = e.cubes.length + e.spheres.length + e.cylinders.length;
      check(primitives >= 1, `entity ${e.id} draws nothing`);
      for (const p of [...e.cubes, ...e.spheres, ...e.cylinders]) {
        check(p.size.x > 0 && p.size.y > 0 && p.size.z > 0, `entity ${e.id}: size ${JSON.stringify(p.size)}`);
      }
    }
  }
}
check(transformsSeen === expectedStates, `${transformsSeen} transforms messages, ${expectedStates} states`);
check(statesSeen === expectedStates, `${statesSeen} state messages, ${expectedStates} states`);
check(updates >= 1, "no SceneUpdate");
let total = 0n;
for (const [id, n] of reader.statistics.channelMessageCounts) {
  check(BigInt(counts.get(topics.get(id)) ?? 0) === n, `Statistics: ${topics.get(id)} count ${n}`);
  total += n;
}
check(total === reader.statistics.messageCount, "Statistics: message count");
check((decompressed > 0) === (expectedCompression === "zstd"), `${decompressed} zstd chunks decompressed`);
await handle.close();
console.log(
  `check_mcap: ok: ${reader.chunkIndexes.length} chunks ('${expectedCompression}'), ${total} messages, ${expectedStates} states of ` +
    `${expectedBodies} bodies bit for bit, ${updates} scene updates, ${types.size} schemas decoded`,
);

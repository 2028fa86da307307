// rigid-view's Foxglove WebSocket at scale: the latency from rigidd's publish (the state's
// stamp_ns, CLOCK_REALTIME, which rigid-view sends as the Message Data timestamp) to the moment a
// Foxglove client (@foxglove/ws-protocol over `ws`, as tests/foxglove) has the message decoded
// with the schema rigid-view advertised (protobufjs): p50, p99, max, messages/s and bytes a
// message. A benchmark, not a test: it asserts nothing (bench/notes/foxglove.md has figures).
//
// It writes a scene of --bodies bodies (a cubic lattice of spinning spheres and boxes, zero gravity,
// --rate Hz, every tick published), starts rigidd on it (own --prefix, DDS on loopback) and
// rigid-view on a free port, then runs each condition for --seconds, --repeat times, interleaved:
//   transforms  one client subscribed to /rigid/transforms (what Foxglove's 3D panel needs)
//   all         one client subscribed to /rigid/transforms, /rigid/body_states and /rigid/state
//               (the 3D panel and plots)
// rigid-view sends at most 60 states a second (as to the page), each as soon as it arrives.
//
// usage: node foxglove_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000] [--seconds 10] [--rate 100]
//                                [--repeat 3]
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { loadavg, tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';

const require = createRequire(fileURLToPath(new URL('../../tests/foxglove/package.json', import.meta.url)));
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const WebSocket = require('ws');
const protobuf = require('protobufjs');
const descriptor = require('protobufjs/ext/descriptor');
const { Processes, sleep, until } = await import('../../tests/view/processes.mjs');

const args = process.argv.slice(2);
const [rigidd, rigidView] = args;
const opt = { bodies: 1000, seconds: 10, rate: 100, repeat: 3 };
for (let i = 2; i < args.length; i += 2) {
  const key = args[i].replace(/^--/, '');
  if (!(key in opt) || !(Number(args[i + 1]) > 0)) {
    console.error(`foxglove_bench: bad option ${args[i]} ${args[i + 1] ?? ''}`);
    process.exit(2);
  }
  opt[key] = Number(args[i + 1]);
}

function sceneText(n) {
  const side = Math.ceil(Math.cbrt(n));
  const lines = [`# foxglove_bench: ${n} bodies`, `world { rate_hz: ${opt.rate}  publish_every: 1  gravity { } }`];
  for (let i = 0; i < n; ++i) {
    const x = (i % side) - (side - 1) / 2, y = (Math.floor(i / side) % side) - (side - 1) / 2;
    const z = Math.floor(i / (side * side)) - (side - 1) / 2;
    const shape = i % 2 ? 'box { x: 0.2 y: 0.12 z: 0.06 }' : 'sphere { radius: 0.08 }';
    lines.push(`body { name: "b${i}" density: 500 shape { ${shape} } ` +
               `position { x: ${(0.3 * x).toFixed(3)} y: ${(0.3 * y).toFixed(3)} z: ${(0.3 * z).toFixed(3)} } ` +
               `angular_velocity { x: ${(i % 7) * 0.3} y: ${(i % 5) * 0.4} z: ${1 + (i % 3)} } }`);
  }
  return lines.join('\n') + '\n';
}

const quantile = (sorted, q) => (sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : NaN);
const median = (xs) => quantile([...xs].sort((a, b) => a - b), 0.5);
const nowNs = () => BigInt(Math.round((performance.timeOrigin + performance.now()) * 1e3)) * 1000n;

// One window: a client subscribed to `topics`; latency of each state message of /rigid/transforms
// from its stamp to its decode.
async function window(url, topics) {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const channels = new Map();
  const subs = new Map();
  client.on('error', () => {});
  client.on('advertise', (list) => {
    for (const ch of list) {
      const set = descriptor.FileDescriptorSet.decode(Buffer.from(ch.schema, 'base64'));
      channels.set(ch.topic, { ...ch, type: protobuf.Root.fromDescriptor(set).lookupType(ch.schemaName) });
    }
  });
  await until('the advertised channels', () => channels.size > 0, 10000);
  const stats = { latencies: [], messages: 0, bytes: 0, bodies: 0, measuring: false };
  client.on('message', ({ subscriptionId, timestamp, data }) => {
    const ch = channels.get(subs.get(subscriptionId));
    const decoded = ch.type.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    const at = nowNs();
    if (!stats.measuring) return;
    ++stats.messages;
    stats.bytes += data.byteLength;
    if (ch.topic === '/rigid/transforms') {
      stats.latencies.push(Number(at - timestamp) / 1e6);
      stats.bodies = decoded.transforms.length;
    }
  });
  for (const t of topics) subs.set(client.subscribe(channels.get(t).id), t);
  await sleep(2000);
  stats.measuring = true;
  await sleep(opt.seconds * 1000);
  stats.measuring = false;
  client.close();
  const l = stats.latencies.sort((a, b) => a - b);
  return { p50: quantile(l, 0.5), p99: quantile(l, 0.99), max: l[l.length - 1], states: l.length / opt.seconds,
           bytes: stats.bytes / Math.max(1, stats.messages), bodies: stats.bodies };
}

const work = mkdtempSync(join(tmpdir(), 'foxglove-bench-'));
const processes = new Processes();
try {
  const sceneFile = join(work, `bench_${opt.bodies}.pbtxt`);
  writeFileSync(sceneFile, sceneText(opt.bodies));
  const bus = ['--transport', 'dds', '--prefix', `foxbench${process.pid}`];
  processes.start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = processes.start(rigidView, [...bus, '--listen', '127.0.0.1:0']);
  const port = await until('rigid-view to print its URL', () => (view.out.match(/127\.0\.0\.1:(\d+)\//) || [])[1], 20000);
  const url = `ws://127.0.0.1:${port}/`;
  const conditions = {
    transforms: ['/rigid/transforms'],
    all: ['/rigid/transforms', '/rigid/body_states', '/rigid/state'],
  };
  const results = Object.fromEntries(Object.keys(conditions).map((k) => [k, []]));
  console.log(`foxglove_bench: ${opt.bodies} bodies at ${opt.rate} Hz, ${opt.seconds} s windows, ` +
              `load average ${loadavg().map((x) => x.toFixed(2)).join(' ')}`);
  for (let r = 0; r < opt.repeat; ++r) {
    for (const [name, topics] of Object.entries(conditions)) {
      const w = await window(url, topics);
      results[name].push(w);
      console.log(`  ${name.padEnd(10)} run ${r + 1}: ${w.bodies} bodies, ${w.states.toFixed(1)} states/s, ` +
                  `latency ms p50 ${w.p50.toFixed(2)} p99 ${w.p99.toFixed(2)} max ${w.max.toFixed(2)}, ` +
                  `${(w.bytes / 1024).toFixed(1)} KiB a message`);
    }
  }
  console.log('medians over the runs:');
  for (const [name, ws] of Object.entries(results)) {
    console.log(`  ${name.padEnd(10)} states/s ${median(ws.map((w) => w.states)).toFixed(1)}, latency ms ` +
                `p50 ${median(ws.map((w) => w.p50)).toFixed(2)} p99 ${median(ws.map((w) => w.p99)).toFixed(2)} ` +
                `(worst p99 ${Math.max(...ws.map((w) => w.p99)).toFixed(2)})`);
  }
  await processes.stop(view);
  console.log(view.err.trim());
} finally {
  processes.stopAll();
  rmSync(work, { recursive: true, force: true });
}

// rigid-view's Foxglove WebSocket at scale: the latency from rigidd's publish (the state's
// stamp_ns, CLOCK_REALTIME, which rigid-view sends as the Message Data timestamp) to the moment a
// Foxglove client (@foxglove/ws-protocol over `ws`, as tests/foxglove) has the message decoded
// with the schema rigid-view advertised (protobufjs): p50, p99, max, messages/s and bytes a
// message; and to its arrival (the library's message event, before the payload's decode). A benchmark, not a test: it asserts nothing (bench/notes/foxglove.md has figures).
//
// It writes a scene of --bodies bodies (a cubic lattice of spinning spheres and boxes, zero gravity,
// --rate Hz, every tick published), starts rigidd on it (own --prefix, DDS on loopback) and
// rigid-view on a free port, then runs each condition for --seconds, --repeat times, interleaved:
//   transforms  one client subscribed to /rigid/transforms (what Foxglove's 3D panel needs)
//   all         one client subscribed to /rigid/transforms, /rigid/body_states and /rigid/state
//               (the 3D panel and plots)
// rigid-view sends at most 60 states a second (as to the page), each as soon as it arrives.
//
// --baseline OLD_RIGID_VIEW: what serving Foxglove costs rigid-view when no Foxglove client is
// connected, instead: both rigid-views (this one and OLD, e.g. built from the commit before) on
// the same rigidd at once, each with no client at all, their CPU time (user + system, /proc) over
// each --seconds window, --repeat windows; the medians and their ratio.
//
// usage: node foxglove_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000] [--seconds 10] [--rate 100]
//                                [--repeat 3] [--baseline OLD_RIGID_VIEW]
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
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
let baseline = null;
for (let i = 2; i < args.length; i += 2) {
  const key = args[i].replace(/^--/, '');
  if (key === 'baseline' && args[i + 1]) {
    baseline = args[i + 1];
    continue;
  }
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
  const stats = { latencies: [], arrivals: [], messages: 0, bytes: 0, bodies: 0, measuring: false };
  client.on('message', ({ subscriptionId, timestamp, data }) => {
    const arrived = nowNs();  // (the library has parsed the 13-byte header, not the payload)
    const ch = channels.get(subs.get(subscriptionId));
    const decoded = ch.type.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    const at = nowNs();
    if (!stats.measuring) return;
    ++stats.messages;
    stats.bytes += data.byteLength;
    if (ch.topic === '/rigid/transforms') {
      stats.latencies.push(Number(at - timestamp) / 1e6);
      stats.arrivals.push(Number(arrived - timestamp) / 1e6);
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
  const a = stats.arrivals.sort((x, y) => x - y);
  return { p50: quantile(l, 0.5), p99: quantile(l, 0.99), max: l[l.length - 1], states: l.length / opt.seconds,
           arrivalP50: quantile(a, 0.5), arrivalP99: quantile(a, 0.99),
           bytes: stats.bytes / Math.max(1, stats.messages), bodies: stats.bodies };
}

// CPU time (s, user + system) of a process, from /proc/PID/stat (fields 14 and 15, in ticks).
function cpuSeconds(pid) {
  const text = readFileSync(`/proc/${pid}/stat`, 'utf8');
  const f = text.slice(text.lastIndexOf(')') + 2).split(' ');
  return (Number(f[11]) + Number(f[12])) / 100;  // sysconf(_SC_CLK_TCK) on Linux
}

// --baseline: both rigid-views with no client, side by side.
async function idleCost(bus) {
  const views = { new: processes.start(rigidView, [...bus, '--listen', '127.0.0.1:0']),
                  old: processes.start(baseline, [...bus, '--listen', '127.0.0.1:0']) };
  for (const [name, v] of Object.entries(views))
    await until(`the ${name} rigid-view to print its URL`, () => /127\.0\.0\.1:\d+\//.test(v.out), 20000);
  await sleep(2000);
  const shares = { new: [], old: [] };
  for (let r = 0; r < opt.repeat; ++r) {
    const before = Object.fromEntries(Object.entries(views).map(([k, v]) => [k, cpuSeconds(v.pid)]));
    await sleep(opt.seconds * 1000);
    for (const [k, v] of Object.entries(views)) shares[k].push((100 * (cpuSeconds(v.pid) - before[k])) / opt.seconds);
    console.log(`  window ${r + 1}: rigid-view ${shares.new[r].toFixed(2)}% of a CPU, baseline ${shares.old[r].toFixed(2)}%`);
  }
  const n = median(shares.new), o = median(shares.old);
  console.log(`medians: rigid-view ${n.toFixed(2)}%, baseline ${o.toFixed(2)}%, ratio ${(n / o).toFixed(3)}`);
}

const work = mkdtempSync(join(tmpdir(), 'foxglove-bench-'));
const processes = new Processes();
try {
  const sceneFile = join(work, `bench_${opt.bodies}.pbtxt`);
  writeFileSync(sceneFile, sceneText(opt.bodies));
  const bus = ['--transport', 'dds', '--prefix', `foxbench${process.pid}`];
  processes.start(rigidd, ['--scene', sceneFile, ...bus]);
  if (baseline) {
    console.log(`foxglove_bench --baseline: ${opt.bodies} bodies at ${opt.rate} Hz, no client, ` +
                `${opt.seconds} s windows, load average ${loadavg().map((x) => x.toFixed(2)).join(' ')}`);
    await idleCost(bus);
  } else {
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
                    `latency ms p50 ${w.p50.toFixed(2)} p99 ${w.p99.toFixed(2)} max ${w.max.toFixed(2)} ` +
                    `(arrival p50 ${w.arrivalP50.toFixed(2)} p99 ${w.arrivalP99.toFixed(2)}), ` +
                    `${(w.bytes / 1024).toFixed(1)} KiB a message`);
      }
    }
    console.log('medians over the runs:');
    for (const [name, ws] of Object.entries(results)) {
      console.log(`  ${name.padEnd(10)} states/s ${median(ws.map((w) => w.states)).toFixed(1)}, latency ms ` +
                  `p50 ${median(ws.map((w) => w.p50)).toFixed(2)} p99 ${median(ws.map((w) => w.p99)).toFixed(2)} ` +
                  `(worst p99 ${Math.max(...ws.map((w) => w.p99)).toFixed(2)}; arrival p50 ` +
                  `${median(ws.map((w) => w.arrivalP50)).toFixed(2)} p99 ${median(ws.map((w) => w.arrivalP99)).toFixed(2)})`);
    }
    await processes.stop(view);
    console.log(view.err.trim());
  }
} finally {
  processes.stopAll();
  rmSync(work, { recursive: true, force: true });
}

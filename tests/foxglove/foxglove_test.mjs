// rigid-view's Foxglove WebSocket protocol, checked by an independent client: @foxglove/ws-protocol's
// FoxgloveClient over the `ws` package, and protobufjs decoding every message with the schema the
// channel advertises (nothing of rigid's own client code). Against rigidd on
// tests/view/scenes/view.pbtxt (one body of each shape, no gravity, 200 Hz):
//   - serverInfo (clientPublish, json) and the advertised channels and schemas;
//   - /rigid/bodies: one entity per body drawing its shape, replacing every earlier entity;
//   - with rigidd paused, /rigid/transforms, /rigid/body_states and /rigid/state equal
//     `rigidctl echo --csv` (17 significant digits: the doubles exactly), timestamps rigidd's stamp;
//   - unsubscribe stops a channel; /rigid/stats arrive;
//   - client publish on /rigid/push moves a body by exactly F t / m (by name and by id), and
//     refuses unknown bodies and bad messages with a status;
//   - a --read-only rigid-view: no clientPublish, an advertise refused, a push that moves nothing;
//   - origins (another refused with 403, one named by --foxglove-origin admitted), the connection
//     cap shared with the pages, and more than 20 bad messages closing the connection.
//
// usage: node foxglove_test.mjs RIGIDD RIGID_VIEW RIGIDCTL SCENE
import { createRequire } from 'node:module';

import { Processes, sleep, until as untilEvery } from '../view/processes.mjs';

const require = createRequire(import.meta.url);
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const WebSocket = require('ws');
const protobuf = require('protobufjs');
const descriptor = require('protobufjs/ext/descriptor');

const [rigidd, rigidView, rigidctl, sceneFile] = process.argv.slice(2);
const prefix = `foxtest${process.pid}`;
const bus = ['--transport', 'dds', '--prefix', prefix];
const processes = new Processes();
const until = (what, check, ms = 15000) => untilEvery(what, check, ms, 20);
const watchdog = setTimeout(() => fail('took more than 100 s'), 100000);

function fail(message) {
  console.error(`foxglove_test: FAILED: ${message}`);
  console.error(processes.stderrs());
  processes.stopAll();
  process.exit(1);
}
function check(ok, what) {
  if (!ok) throw new Error(what);
}

// A Foxglove client: its serverInfo, channels (with a decoder per schema), statuses, and per
// topic the messages received, decoded, with their Message Data timestamps.
async function connect(url, options = {}) {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], options);
  const client = new FoxgloveClient({ ws });
  const c = { client, ws, info: null, channels: new Map(), statuses: [], received: new Map(), closed: null, subs: new Map() };
  client.on('serverInfo', (i) => { c.info = i; });
  client.on('status', (s) => c.statuses.push(s));
  client.on('close', (e) => { c.closed = e; });
  client.on('error', () => {});
  client.on('advertise', (channels) => {
    for (const ch of channels) {
      const set = descriptor.FileDescriptorSet.decode(Buffer.from(ch.schema, 'base64'));
      const type = protobuf.Root.fromDescriptor(set).lookupType(ch.schemaName);
      c.channels.set(ch.topic, { ...ch, type });
    }
  });
  client.on('message', ({ subscriptionId, timestamp, data }) => {
    const topic = c.subs.get(subscriptionId);
    const ch = c.channels.get(topic);
    const message = ch.type.toObject(ch.type.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)),
                                     { longs: String, defaults: true });
    if (!c.received.has(topic)) c.received.set(topic, []);
    const list = c.received.get(topic);
    list.push({ timestamp, message });
    if (list.length > 400) list.shift();
  });
  c.subscribe = (topic) => {
    const id = client.subscribe(c.channels.get(topic).id);
    c.subs.set(id, topic);
    return id;
  };
  c.latest = (topic) => { const l = c.received.get(topic); return l && l.length ? l[l.length - 1] : null; };
  c.count = (topic) => (c.received.get(topic) || []).length;
  await until('serverInfo and the channels', () => c.info && c.channels.size > 0 || c.closed);
  return c;
}

// The HTTP status a WebSocket handshake with these headers gets (101 when it opens).
function handshake(url, options) {
  return new Promise((resolve) => {
    const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], options);
    ws.on('open', () => resolve({ status: 101, ws }));
    ws.on('unexpected-response', (_req, res) => resolve({ status: res.statusCode }));
    ws.on('error', () => resolve({ status: -1 }));
  });
}

const rigidctlRun = async (args, ms = 20000) => {
  const p = processes.start(rigidctl, [...args, ...bus]);
  const code = await Processes.exited(p, ms);
  if (code !== 0) throw new Error(`rigidctl ${args.join(' ')}: exit ${code}: ${p.err}`);
  return p.out;
};

async function main() {
  processes.start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = processes.start(rigidView, [...bus, '--listen', '127.0.0.1:0']);
  const port = await until('rigid-view to print its URL', () => (view.out.match(/127\.0\.0\.1:(\d+)\//) || [])[1]);
  const url = `ws://127.0.0.1:${port}/`;

  const c = await connect(url);
  check(c.info.capabilities.includes('clientPublish'), `capabilities ${JSON.stringify(c.info.capabilities)}`);
  check(JSON.stringify(c.info.supportedEncodings) === '["json"]', `supportedEncodings ${JSON.stringify(c.info.supportedEncodings)}`);
  const topics = { '/rigid/transforms': 'foxglove.FrameTransforms', '/rigid/bodies': 'foxglove.SceneUpdate',
                   '/rigid/body_states': 'rigid.msgs.BodyStates', '/rigid/state': 'rigid.msgs.StateRecord',
                   '/rigid/scene': 'rigid.msgs.SceneRecord', '/rigid/stats': 'rigid.msgs.StatsRecord' };
  for (const [topic, schema] of Object.entries(topics)) {
    const ch = c.channels.get(topic);
    check(ch && ch.encoding === 'protobuf' && ch.schemaName === schema && ch.schemaEncoding === 'protobuf',
          `channel ${topic}: ${JSON.stringify(ch && { ...ch, schema: undefined, type: undefined })}`);
  }
  check(c.channels.size === 6, `${c.channels.size} channels advertised`);

  for (const t of ['/rigid/bodies', '/rigid/transforms', '/rigid/body_states', '/rigid/state', '/rigid/stats'])
    c.subscribe(t);

  // The scene's entities: each body's shape in its own frame, after a deletion of all.
  await until('a SceneUpdate', () => c.count('/rigid/bodies') > 0);
  const update = c.latest('/rigid/bodies').message;
  check(update.deletions.length === 1 && update.deletions[0].type === 1, `deletions ${JSON.stringify(update.deletions)}`);
  const entities = new Map(update.entities.map((e) => [e.id, e]));
  check(entities.size === 6, `${entities.size} entities`);
  for (const [name, e] of entities) check(e.frame_id === name && e.frame_locked, `entity ${name}: frame ${e.frame_id}`);
  const size = (p) => [p.size.x, p.size.y, p.size.z].map((x) => +x.toFixed(9)).join(' ');
  check(size(entities.get('ball').spheres[0]) === '0.3 0.3 0.3', `ball ${size(entities.get('ball').spheres[0])}`);
  check(size(entities.get('spinner').cubes[0]) === '0.6 0.3 0.1', 'spinner');
  check(size(entities.get('can').cylinders[0]) === '0.2 0.2 0.4', 'can');
  check(entities.get('pill').cylinders.length === 1 && entities.get('pill').spheres.length === 2, 'pill: a cylinder and two caps');
  check(size(entities.get('egg').spheres[0]) === '0.4 0.24 0.2', 'egg');
  check(entities.get('lump').cubes.length === 1, 'lump: the box of its moments');

  // Exact states: paused, the newest messages against rigidctl echo's.
  await until('states on every channel', () => ['/rigid/transforms', '/rigid/body_states', '/rigid/state'].every((t) => c.count(t) > 3));
  await rigidctlRun(['pause']);
  const rows = (await rigidctlRun(['echo', '--csv', '--count', '1', '--timeout', '10'])).trim().split('\n').slice(1).map((l) => l.split(','));
  const t = Number(rows[0][0]);
  const echo = new Map(rows.map((r) => [r[1], r.slice(2).map(Number)]));
  check(echo.size === 6, `rigidctl echo: ${rows.length} rows`);
  await until(`body_states at t=${t}`, () => c.latest('/rigid/body_states')?.message.sim_time === t, 5000);
  const bs = c.latest('/rigid/body_states');
  const tf = c.received.get('/rigid/transforms').find((m) => m.timestamp === bs.timestamp);
  const st = c.received.get('/rigid/state').find((m) => m.timestamp === bs.timestamp);
  check(tf && st, 'a transforms and a state message with the body states\' timestamp');
  const stampNs = BigInt(bs.message.timestamp.seconds) * 1000000000n + BigInt(bs.message.timestamp.nanos);
  check(stampNs === bs.timestamp && BigInt(st.message.stamp_ns) === stampNs, `timestamps: ${bs.timestamp} ${stampNs} ${st.message.stamp_ns}`);
  check(bs.message.bodies.length === 6 && tf.message.transforms.length === 6, 'six bodies in each');
  const ids = st.message.ids;
  for (const [i, b] of bs.message.bodies.entries()) {
    const e = echo.get(b.name);
    check(e, `body ${b.name} not in rigidctl's rows`);
    const mine = [b.position.x, b.position.y, b.position.z, b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z,
                  b.linear_velocity.x, b.linear_velocity.y, b.linear_velocity.z, b.angular_velocity.x, b.angular_velocity.y, b.angular_velocity.z];
    check(mine.every((x, k) => x === e[k]), `${b.name}: body_states ${mine} != rigidctl ${e}`);
    const f = tf.message.transforms[i];
    check(f.parent_frame_id === 'world' && f.child_frame_id === b.name, `transform ${i}: ${f.parent_frame_id} -> ${f.child_frame_id}`);
    const pose = [f.translation.x, f.translation.y, f.translation.z, f.rotation.w, f.rotation.x, f.rotation.y, f.rotation.z];
    check(pose.every((x, k) => x === e[k]), `${b.name}: transform ${pose} != rigidctl ${e.slice(0, 7)}`);
    const fstamp = BigInt(f.timestamp.seconds) * 1000000000n + BigInt(f.timestamp.nanos);
    check(fstamp === stampNs, `${b.name}: transform stamp ${fstamp} != ${stampNs}`);
    check(ids[i] === b.id, `ids: ${ids[i]} != ${b.id}`);
    const s = [0, 1, 2].map((k) => st.message.position[3 * i + k]);
    check(s.every((x, k) => x === e[k]), `${b.name}: /rigid/state position ${s}`);
  }
  const spinner = bs.message.bodies.find((b) => b.name === 'spinner');
  check(Math.abs(spinner.orientation.w) < 0.9999, 'the spinner has not turned');
  console.log(`paused at t=${t}: transforms, body_states and state equal rigidctl echo's`);

  // A client that subscribes while rigidd is paused gets the newest state at once.
  const late = await connect(url);
  late.subscribe('/rigid/body_states');
  await until('the newest state for a late subscriber', () => late.latest('/rigid/body_states')?.message.sim_time === t, 5000);
  late.client.close();
  await rigidctlRun(['resume']);
  await until('stats', () => c.count('/rigid/stats') > 0, 5000);
  check(typeof c.latest('/rigid/stats').message.lateness_p99_us === 'number' && c.latest('/rigid/stats').message.tick > 0, `stats ${JSON.stringify(c.latest('/rigid/stats').message).slice(0, 200)}`);

  // Unsubscribe: /rigid/state stops while the others go on.
  const stateSub = [...c.subs].find(([, topic]) => topic === '/rigid/state')[0];
  c.client.unsubscribe(stateSub);
  await sleep(200);
  const stateCount = c.count('/rigid/state'), tfCount = c.count('/rigid/transforms');
  await sleep(500);
  check(c.count('/rigid/state') === stateCount, 'states after unsubscribe');
  check(c.count('/rigid/transforms') > tfCount || c.count('/rigid/transforms') === 400, 'no transforms while resumed');

  // Client publish: a push of F for t moves the ball (no gravity, at rest) to v = F t / m.
  const ballV = () => c.latest('/rigid/body_states').message.bodies.find((b) => b.name === 'ball').linear_velocity;
  check(ballV().z === 0, `the ball moves before the push: ${JSON.stringify(ballV())}`);
  const pushChannel = c.client.advertise({ topic: '/rigid/push', encoding: 'json', schemaName: 'rigid.Push' });
  const publish = (client, channel, obj) => client.sendMessage(channel, new TextEncoder().encode(typeof obj === 'string' ? obj : JSON.stringify(obj)));
  publish(c.client, pushChannel, { body: 'ball', force: [0, 0, 10], duration: 0.5 });
  const mass = 1000 * (4 / 3) * Math.PI * 0.15 ** 3;
  const expected = (10 * 0.5) / mass;
  await until('the push to end', () => Math.abs(ballV().z - expected) < 1e-9 * expected, 5000);
  await sleep(100);
  check(Math.abs(ballV().z - expected) < 1e-9 * expected, `ball v_z ${ballV().z}, expected ${expected}`);
  const canId = bs.message.bodies.find((b) => b.name === 'can').id;
  publish(c.client, pushChannel, { body: canId, force: [4, 0, 0], duration: 0.1 });
  const canV = () => c.latest('/rigid/body_states').message.bodies.find((b) => b.name === 'can').linear_velocity.x;
  await until('the can pushed by id', () => canV() > 0, 5000);
  console.log(`client publish: ball v_z ${ballV().z} (F t / m = ${expected}), can v_x ${canV()}`);
  const statuses = c.statuses.length;
  publish(c.client, pushChannel, { body: 'nobody', force: [1, 0, 0], duration: 0.1 });
  publish(c.client, pushChannel, '{"body":"ball","force":[1,0],"duration":0.1}');
  publish(c.client, pushChannel, { body: 'ball', force: [1, 0, 0], duration: 99 });
  await until('three refusals', () => c.statuses.length >= statuses + 3, 5000);
  const said = c.statuses.slice(statuses).map((s) => s.message).join(' | ');
  check(/no body named nobody/.test(said) && /force: expected \[x, y, z\]/.test(said) && /duration/.test(said), `statuses: ${said}`);

  // --read-only: no clientPublish; an advertise refused; the egg does not move. Also admits the
  // origin named by --foxglove-origin.
  const ro = processes.start(rigidView, [...bus, '--listen', '127.0.0.1:0', '--read-only', '--foxglove-origin', 'https://app.example']);
  const roPort = await until('the read-only rigid-view', () => (ro.out.match(/127\.0\.0\.1:(\d+)\//) || [])[1]);
  const roUrl = `ws://127.0.0.1:${roPort}/`;
  const r = await connect(roUrl);
  check(!r.info.capabilities.includes('clientPublish'), `read-only capabilities ${JSON.stringify(r.info.capabilities)}`);
  const roChannel = r.client.advertise({ topic: '/rigid/push', encoding: 'json', schemaName: 'rigid.Push' });
  publish(r.client, roChannel, { body: 'egg', force: [0, 50, 0], duration: 0.5 });
  await until('the read-only refusals', () => r.statuses.length >= 2, 5000);
  check(/read-only/.test(r.statuses[0].message), `read-only status: ${r.statuses[0].message}`);
  await sleep(800);
  const egg = c.latest('/rigid/body_states').message.bodies.find((b) => b.name === 'egg').linear_velocity;
  check(egg.x === 0 && egg.y === 0 && egg.z === 0, `the egg moved under a read-only rigid-view: ${JSON.stringify(egg)}`);

  // Origins: another is refused (403), the named one admitted; the page's own admitted.
  check((await handshake(roUrl, { origin: 'https://elsewhere.example' })).status === 403, 'a foreign origin was not refused');
  await until('the refused origin named on stderr', () => /refused a Foxglove client from origin 'https:\/\/elsewhere\.example' \(rigid-view --foxglove-origin/.test(ro.err), 5000);
  const admitted = await handshake(roUrl, { origin: 'https://app.example' });
  check(admitted.status === 101, `--foxglove-origin's origin: ${admitted.status}`);
  admitted.ws.close();
  const own = await handshake(roUrl, { origin: `http://127.0.0.1:${roPort}` });
  check(own.status === 101, `the page's origin: ${own.status}`);
  own.ws.close();

  // The cap: pages and Foxglove clients together, at most 16 (r is one).
  await sleep(200);
  const many = [];
  for (let k = 0; k < 15; ++k) many.push(await handshake(roUrl, {}));
  check(many.every((h) => h.status === 101), `the first 16 connections: ${many.map((h) => h.status)}`);
  check((await handshake(roUrl, {})).status === 503, 'the 17th connection was not refused');
  for (const h of many) h.ws.close();
  r.client.close();
  await sleep(200);

  // More than 20 bad messages close the connection (policy error, 1008); 20 keep it.
  const b = await connect(roUrl);
  for (let k = 0; k < 20; ++k) b.ws.send(k % 2 ? 'garbage' : '{"op":"getParameters","parameterNames":[]}');
  await until('20 refusals', () => b.statuses.length >= 20, 5000);
  check(b.closed === null, 'closed after 20 bad messages');
  b.ws.send(new Uint8Array([7, 1, 2]));
  await until('the connection closed after 21 bad messages', () => b.closed, 5000);
  check(b.closed.code === 1008, `close code ${b.closed.code}`);

  c.client.close();
  await processes.stop(view);
  check(/foxglove clients [1-9]\d*, messages sent [1-9]/.test(view.err), `rigid-view's summary: ${view.err}`);
  console.log('foxglove_test: passed');
}

main().then(() => {
  clearTimeout(watchdog);
  processes.stopAll();
  console.log('1 passed, 0 failed');
}, (e) => fail(e.stack || e.message));

// rigidd --ros seen by a ROS 2 peer that shares no code with rigid: a pure-JS RTPS stack
// (@foxglove/rtps, which discovers by multicast SPDP as ROS 2 does) decoding with ROS 2's own
// message definitions (@foxglove/rosmsg-msgs-common, @foxglove/rosmsg2-serialization). rigid's
// own state is read from rigid/state, decoded by hand from msgs/rigid.idl's WorldState.
//
//   node ros_node_test.mjs DOMAIN NAMESPACE DISTRO     (NAMESPACE "" or "/lab"; DISTRO humble|jazzy)
//
// Checks, for tests/ros/scenes/ros_shapes.pbtxt served by `rigidd --ros` on DOMAIN:
//  - the participant's USER_DATA is "enclave=/;" (what rmw_cyclonedds puts there);
//  - every ROS topic, with its DDS name (rt/..., rq/...Request, rr/...Reply), type name
//    (pkg::msg::dds_::Name_), reliability and durability; one wrench reader per body whose name
//    ROS topics can carry ("my.box" has none); each service's request reader and reply writer
//    share one "serviceid";
//  - /tf: one transform per body, parent "world", child the body's name, stamp the state's sim
//    time in ns, translation and rotation equal bit for bit to rigid/state's for that tick, over
//    at least 20 states;
//  - /clock: equal to a state's sim time;
//  - /tf_static (transient local): world -> each static part (planes and fixed shapes) at its
//    pose, a plane's frame on the plane with z along its normal;
//  - rigid/markers: each body's shape, scale, colour and frame (transient local: read late), and
//    each static part's;
//  - ros_discovery_info: node "rigidd" in NAMESPACE listing exactly the GUIDs of its ROS readers
//    and writers, with GIDs of DISTRO's size (Humble 24 bytes, later 16).
// Exits 0 when all hold, 1 with one line per failure.
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const rtps = require("@foxglove/rtps");
const { UdpSocketNode } = require("@foxglove/rtps/nodejs");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const { parse } = require("@foxglove/rosmsg");
const { CdrReader } = require("@foxglove/cdr");
const common = require("@foxglove/rosmsg-msgs-common");

const [domainArg, nsArg, distro] = process.argv.slice(2);
const domainId = Number(domainArg);
const ns = nsArg ?? "";
const defs = distro === "humble" ? common.ros2humble : common.ros2jazzy;

const failures = [];
const check = (ok, what) => {
  if (!ok) failures.push(what);
  return ok;
};

function readerFor(type) {
  const root = defs[type];
  return new MessageReader([root, ...Object.values(defs).filter((d) => d !== root)]);
}

// rmw_dds_common/msg/ParticipantEntitiesInfo, from its .msg files (Gid: char[24] in Humble,
// char[16] later).
const gidSize = distro === "humble" ? 24 : 16;
const discoveryReader = new MessageReader(
  parse(
    `Gid gid
NodeEntitiesInfo[] node_entities_info_seq
================================================================================
MSG: rmw_dds_common/Gid
char[${gidSize}] data
================================================================================
MSG: rmw_dds_common/NodeEntitiesInfo
string<=256 node_namespace
string<=256 node_name
Gid[] reader_gid_seq
Gid[] writer_gid_seq`,
    { ros2: true },
  ),
);

// The test scene's bodies (tests/ros/scenes/ros_shapes.pbtxt) and the marker each should get:
// [name, marker type, scale].
const SPHERE = 2;
const CUBE = 1;
const CYLINDER = 3;
const bodies = [
  ["ball", SPHERE, [0.5, 0.5, 0.5]],
  ["twin", SPHERE, [0.5, 0.5, 0.5]],
  ["spinner", CUBE, [0.3, 0.2, 0.1]],
  ["arm/link_1", CYLINDER, [0.2, 0.2, 0.6]],
  ["pill", CYLINDER, [0.1, 0.1, 0.4]],
  ["egg", SPHERE, [0.2, 0.3, 0.4]],
  ["my.box", CUBE, [0.1, 0.1, 0.1]],
  ["dot", SPHERE, [0.1, 0.1, 0.1]],
];
// rigid-view's palette (clients/view/web/app.js), by the body's place in the scene.
const palette = [0x4fc3f7, 0xffb74d, 0x81c784, 0xe57373, 0xba68c8, 0xfff176, 0x90a4ae];
// The scene's static parts: [name, translation, rotation (w x y z), marker type, scale, z offset].
const h = Math.SQRT1_2;
const statics = [
  ["ground", [0, 0, -3], [1, 0, 0, 0], CUBE, [20, 20, 0.002], -0.001],
  ["wall", [5, 0, 0], [h, 0, h, 0], CUBE, [20, 20, 0.002], -0.001],
  ["ramp", [3, 0, -2], [0.9659258262890683, 0, 0.25881904510252074, 0], CUBE, [2, 1, 0.1], 0],
  ["post", [-3, 3, 0], [1, 0, 0, 0], CYLINDER, [0.2, 0.2, 1], 0],
];
const services = [
  ["get_simulator_features", "GetSimulatorFeatures"],
  ["get_simulation_state", "GetSimulationState"],
  ["set_simulation_state", "SetSimulationState"],
  ["step_simulation", "StepSimulation"],
  ["reset_simulation", "ResetSimulation"],
  ["get_entity_state", "GetEntityState"],
  ["set_entity_state", "SetEntityState"],
  ["get_entities", "GetEntities"],
];
const msg = (pkg, name) => `${pkg}::msg::dds_::${name}_`;
const { Reliable } = rtps.Reliability;
const { Volatile, TransientLocal } = rtps.Durability;
const expectedWriters = new Map([
  [`rt${ns}/tf`, [msg("tf2_msgs", "TFMessage"), Reliable, Volatile]],
  [`rt${ns}/tf_static`, [msg("tf2_msgs", "TFMessage"), Reliable, TransientLocal]],
  ["rt/clock", [msg("rosgraph_msgs", "Clock"), Reliable, Volatile]],
  [`rt${ns}/rigid/markers`, [msg("visualization_msgs", "MarkerArray"), Reliable, TransientLocal]],
  ["ros_discovery_info", [msg("rmw_dds_common", "ParticipantEntitiesInfo"), Reliable, TransientLocal]],
]);
const expectedReaders = new Map();
for (const [name] of bodies) {
  if (name === "my.box") continue;  // not a ROS name: no topic
  expectedReaders.set(`rt${ns}/rigid/${name}/wrench`, [msg("geometry_msgs", "WrenchStamped"), Reliable, Volatile]);
}
for (const [name, type] of services) {
  const base = `${ns}/rigidd/${name}`;
  expectedWriters.set(`rr${base}Reply`, [`simulation_interfaces::srv::dds_::${type}_Response_`, Reliable, Volatile]);
  expectedReaders.set(`rq${base}Request`, [`simulation_interfaces::srv::dds_::${type}_Request_`, Reliable, Volatile]);
}

const near = (a, b) => Math.abs(a - b) < 1e-12;
const guidOf = (e) => e.guidPrefix + e.entityId.toString(16).padStart(8, "0");
const hex = (bytes) => Buffer.from(bytes).toString("hex");

const participant = new rtps.Participant({
  name: "ros_node_test",
  addresses: ["127.0.0.1"],
  domainId,
  udpSocketCreate: UdpSocketNode.Create,
});
let rigidd;  // the rigidd participant's attributes
const writers = new Map();
const readers = new Map();
participant.on("discoveredParticipant", (p) => {
  if (p.userData?.startsWith("enclave=")) rigidd = p;
});
participant.on("discoveredPublication", (e) => e.topicName && writers.set(e.topicName, e));
participant.on("discoveredSubscription", (e) => e.topicName && readers.set(e.topicName, e));
await participant.start();

const subscribe = (topicName, typeName, reliability, durability) =>
  participant.subscribe({
    topicName,
    typeName,
    durability,
    reliability: { kind: reliability, maxBlockingTime: { sec: 0, nsec: 0 } },
    history: { kind: rtps.HistoryKind.KeepLast, depth: 1000 },
  });
subscribe("rigid/state", "rigid::WorldState", rtps.Reliability.BestEffort, Volatile);
subscribe(`rt${ns}/tf`, msg("tf2_msgs", "TFMessage"), Reliable, Volatile);
subscribe("rt/clock", msg("rosgraph_msgs", "Clock"), Reliable, Volatile);
subscribe(`rt${ns}/rigid/markers`, msg("visualization_msgs", "MarkerArray"), Reliable, TransientLocal);
subscribe(`rt${ns}/tf_static`, msg("tf2_msgs", "TFMessage"), Reliable, TransientLocal);
subscribe("ros_discovery_info", msg("rmw_dds_common", "ParticipantEntitiesInfo"), Reliable, TransientLocal);

// msgs/rigid.idl WorldState: tick, sim_time, stamp_ns, ids, position (3n), orientation (4n, w x y
// z), linear and angular velocity.
function decodeState(data) {
  const r = new CdrReader(data);
  const tick = r.int64();
  const simTime = r.float64();
  r.int64();
  const ids = r.int32Array(r.sequenceLength());
  const position = r.float64Array(r.sequenceLength());
  const orientation = r.float64Array(r.sequenceLength());
  return { tick, simTime, ids, position, orientation };
}

const tfReader = readerFor("tf2_msgs/TFMessage");
const clockReader = readerFor("rosgraph_msgs/Clock");
const markerReader = readerFor("visualization_msgs/MarkerArray");
const ns9 = (t) => BigInt(t.sec) * 1_000_000_000n + BigInt(t.nanosec);
const simNs = (s) => BigInt(Math.round(s * 1e9));

const states = new Map();  // sim time in ns -> state
const tfs = [];
const clocks = [];
let markers;
let tfStatic;
let discovery;
participant.on("userData", (u) => {
  const topic = u.publication.topicName;
  try {
    if (topic === "rigid/state") {
      const s = decodeState(u.serializedData);
      states.set(simNs(s.simTime), s);
    } else if (topic === `rt${ns}/tf`) {
      tfs.push(tfReader.readMessage(u.serializedData));
    } else if (topic === "rt/clock") {
      clocks.push(clockReader.readMessage(u.serializedData));
    } else if (topic === `rt${ns}/tf_static`) {
      tfStatic = tfReader.readMessage(u.serializedData);
    } else if (topic === `rt${ns}/rigid/markers`) {
      markers = markerReader.readMessage(u.serializedData);
    } else if (topic === "ros_discovery_info" && guidOf(u.publication).startsWith(rigidd?.guidPrefix ?? "-")) {
      discovery = discoveryReader.readMessage(u.serializedData);
    }
  } catch (e) {
    check(false, `${topic}: does not decode: ${e.message}`);
  }
});

// Wait for 20 /tf messages that have their state, and for the rest, at most 20 s.
const matched = () => tfs.filter((m) => states.has(ns9(m.transforms[0]?.header.stamp ?? { sec: 0, nanosec: 0 }))).length;
const start = Date.now();
while (Date.now() - start < 20000 && !(matched() >= 20 && markers && tfStatic && discovery && clocks.length >= 5 && rigidd)) {
  await new Promise((r) => setTimeout(r, 50));
}
await participant.shutdown();

check(rigidd !== undefined, "no participant with an enclave in its USER_DATA");
if (rigidd) check(rigidd.userData === "enclave=/;", `participant USER_DATA '${rigidd.userData}', not 'enclave=/;'`);

// Topics, types and QoS.
const fromRigidd = (e) => rigidd && e.guidPrefix === rigidd.guidPrefix;
const checkEndpoints = (seen, expected, kind) => {
  for (const [topic, [type, reliability, durability]] of expected) {
    const e = seen.get(topic);
    if (!check(e && fromRigidd(e), `no ${kind} of ${topic} from rigidd`)) continue;
    check(e.typeName === type, `${topic}: type ${e.typeName}, not ${type}`);
    check(e.reliability.kind === reliability, `${topic}: reliability ${e.reliability.kind}, not ${reliability}`);
    check(e.durability === durability, `${topic}: durability ${e.durability}, not ${durability}`);
  }
  for (const [topic, e] of seen) {
    const ros = /^(rt|rq|rr)\//.test(topic) || topic === "ros_discovery_info";
    if (ros && fromRigidd(e)) check(expected.has(topic), `unexpected ${kind} of ${topic}`);
  }
};
checkEndpoints(writers, expectedWriters, "writer");
checkEndpoints(readers, expectedReaders, "reader");
for (const [name] of services) {
  const w = writers.get(`rr${ns}/rigidd/${name}Reply`);
  const r = readers.get(`rq${ns}/rigidd/${name}Request`);
  if (w && r) {
    check(/^serviceid=[^;]+;$/.test(w.userData ?? ""), `${name}: reply writer USER_DATA '${w.userData}'`);
    check(w.userData === r.userData, `${name}: request reader and reply writer have other serviceids`);
  }
}

// /tf against rigid/state, bit for bit.
let compared = 0;
for (const m of tfs) {
  const stamp = m.transforms[0]?.header.stamp;
  const s = stamp && states.get(ns9(stamp));
  if (!s) continue;
  compared += 1;
  if (!check(m.transforms.length === bodies.length, `/tf has ${m.transforms.length} transforms, not ${bodies.length}`)) break;
  m.transforms.forEach((t, i) => {
    const where = `/tf at tick ${s.tick}, ${bodies[i][0]}`;
    check(ns9(t.header.stamp) === simNs(s.simTime), `${where}: stamp differs from the state's sim time`);
    check(t.header.frame_id === "world", `${where}: parent '${t.header.frame_id}'`);
    check(t.child_frame_id === bodies[s.ids[i]][0], `${where}: child '${t.child_frame_id}'`);
    const p = [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z];
    const q = [t.transform.rotation.w, t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z];
    p.forEach((v, k) => check(Object.is(v, s.position[3 * i + k]), `${where}: translation[${k}] ${v} != ${s.position[3 * i + k]}`));
    q.forEach((v, k) => check(Object.is(v, s.orientation[4 * i + k]), `${where}: rotation (w x y z)[${k}] ${v} != ${s.orientation[4 * i + k]}`));
  });
}
check(compared >= 20, `only ${compared} /tf messages matched a rigid/state (of ${tfs.length} /tf, ${states.size} states)`);
const moving = new Set(tfs.map((m) => m.transforms[2]?.transform.rotation.x));
check(moving.size > 1, "/tf never changed: the spinner does not spin");

// /clock: each a state's sim time.
check(clocks.length >= 5, `only ${clocks.length} /clock messages`);
const clockMatches = clocks.filter((c) => states.has(ns9(c.clock))).length;
check(clockMatches >= Math.min(5, clocks.length), `only ${clockMatches} of ${clocks.length} /clock values are a state's sim time`);

// Markers.
if (check(markers !== undefined, `no rigid/markers (transient local) received`)) {
  const main = markers.markers.filter((m) => m.ns === "rigid");
  const ends = markers.markers.filter((m) => m.ns === "rigid_capsule_ends");
  const fixed = markers.markers.filter((m) => m.ns === "rigid_static");
  const fixedEnds = markers.markers.filter((m) => m.ns === "rigid_static_capsule_ends");
  check(fixed.length === statics.length, `${fixed.length} static markers, not ${statics.length}`);
  check(fixedEnds.length === 2 && fixedEnds.every((m) => m.header.frame_id === "post"),
        "the static capsule 'post' has no two ends");
  fixed.forEach((m, i) => {
    const [name, , , type, scale, z] = statics[i] ?? [];
    const where = `static marker ${i} (${name})`;
    const s = [m.scale.x, m.scale.y, m.scale.z];
    check(m.header.frame_id === name && m.type === type && s.every((v, k) => near(v, scale[k])) &&
          near(m.pose.position.z, z), `${where}: frame '${m.header.frame_id}', type ${m.type}, scale ${s}, z ${m.pose.position.z}`);
  });
  check(main.length === bodies.length, `${main.length} body markers, not ${bodies.length}`);
  check(ends.length === 2 && ends.every((m) => m.header.frame_id === "pill" && m.type === SPHERE),
        "the capsule 'pill' has no two SPHERE ends");
  main.forEach((m, i) => {
    const [name, type, scale] = bodies[i];
    const where = `marker ${i} (${name})`;
    check(m.header.frame_id === name && m.id === i, `${where}: frame '${m.header.frame_id}', id ${m.id}`);
    check(m.type === type, `${where}: type ${m.type}, not ${type}`);
    check(m.frame_locked === true && m.action === 0, `${where}: not an ADD locked to its frame`);
    const s = [m.scale.x, m.scale.y, m.scale.z];
    check(s.every((v, k) => Math.abs(v - scale[k]) < 1e-12), `${where}: scale ${s}, not ${scale}`);
    const rgb = palette[i % palette.length];
    const c = [m.color.r, m.color.g, m.color.b].map((v) => Math.round(v * 255));
    check(c[0] === rgb >> 16 && c[1] === ((rgb >> 8) & 255) && c[2] === (rgb & 255) && m.color.a === 1,
          `${where}: colour ${c}, not rigid-view's #${rgb.toString(16)}`);
  });
}

// /tf_static: each static part at its pose under world (to rounding: the plane's frame is computed).
if (check(tfStatic !== undefined, "no /tf_static (transient local) received")) {
  check(tfStatic.transforms.length === statics.length, `/tf_static has ${tfStatic.transforms.length} transforms, not ${statics.length}`);
  tfStatic.transforms.forEach((t, i) => {
    const [name, p, q] = statics[i] ?? [];
    const where = `/tf_static ${i} (${name})`;
    check(t.header.frame_id === "world" && t.child_frame_id === name, `${where}: '${t.header.frame_id}' -> '${t.child_frame_id}'`);
    const tp = [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z];
    const tq = [t.transform.rotation.w, t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z];
    check(tp.every((v, k) => near(v, p[k])) && tq.every((v, k) => near(v, q[k])),
          `${where}: pose ${tp} ${tq}, not ${p} ${q}`);
  });
}

// ros_discovery_info: what ros2 node list / ros2 node info read.
if (check(discovery !== undefined, "no ros_discovery_info from rigidd") && rigidd) {
  check(hex(discovery.gid.data) === rigidd.guidPrefix + "000001c1" + "00".repeat(gidSize - 16),
        `ros_discovery_info gid ${hex(discovery.gid.data)} is not the participant's GUID in ${gidSize} bytes`);
  const nodes = discovery.node_entities_info_seq;
  if (check(nodes.length === 1, `${nodes.length} nodes in ros_discovery_info`)) {
    const n = nodes[0];
    check(n.node_name === "rigidd" && n.node_namespace === (ns || "/"),
          `node '${n.node_namespace}' '${n.node_name}', not '${ns || "/"}' 'rigidd'`);
    const gids = (list) => new Set(list.map((g) => hex(g.data).slice(0, 32)));
    const guids = (seen, expected) =>
      new Set([...expected.keys()].filter((t) => t !== "ros_discovery_info" && seen.get(t)).map((t) => guidOf(seen.get(t))));
    const same = (a, b) => a.size === b.size && [...a].every((x) => b.has(x));
    check(same(gids(n.reader_gid_seq), guids(readers, expectedReaders)), "the node's reader GIDs are not its ROS readers' GUIDs");
    check(same(gids(n.writer_gid_seq), guids(writers, expectedWriters)), "the node's writer GIDs are not its ROS writers' GUIDs");
  }
}

for (const f of failures.slice(0, 40)) console.log(`ros_node_test: FAILED: ${f}`);
if (failures.length > 40) console.log(`ros_node_test: ... ${failures.length - 40} more`);
console.log(`ros_node_test: domain ${domainId} ns '${ns}' ${distro}: ${compared} /tf messages compared, ${clocks.length} /clock, ${failures.length} failures`);
process.exit(failures.length === 0 ? 0 : 1);

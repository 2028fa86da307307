// rigid-view in a real browser: rigidd on a small scene (unique --prefix), rigid-view on a free
// port, the page in Debian's headless Chromium (playwright-core, never a downloaded browser).
// Checks: no console errors; the scene's bodies drawn, as instances (one per body); the pose and
// velocities the page holds for a spinning body equal the state rigidd published (read
// independently with rigidctl echo --csv); pause, step, reset and resume answered by rigidd; a
// mouse drag on a body pushes it in the direction of the drag (velocity read with rigidctl), with a
// wrench arrow drawn while pushing, and the push stops after release; the energy and momentum
// drifts rigid-view sends named by body, the spinner's small, the pushed ball's small once the
// push ended; hover axes, search, selection, follow, trails; the drift and lateness plots receive data; garbage from a page refused; a page
// that acknowledges no state gets two. A pure torque in the body frame sent to the spinning body
// (view_send_torque): a torque arrow about R_WB tau_B through the body's origin, turning by the
// right-hand rule, drawn with exactly the states the wrench's ticks produced and gone after its
// ttl. Screenshot: OUTDIR/rigid-view.png.
// A large scene (view_many.pbtxt beside SCENE: more than the page's kManyBodies, drawn as ray-cast
// impostors posed in the vertex shader): every body drawn, the pose the shader gets for the
// spinning probe equal to the state rigidd published (float32), the probe's colour on the screen
// where its published pose projects and the background where no body is, its drawn silhouette
// the true box's (the page's exact CPU ray cast against the pixels around it), and hover picking
// the probe.
// usage: node browser_test.mjs RIGIDD RIGID_VIEW RIGIDCTL SCENE OUTDIR SEND_TORQUE
import { mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { chromium } from 'playwright-core';

import { browserHarness, Processes, sleep, until as untilOr } from './processes.mjs';

const [rigidd, rigidView, rigidctl, sceneFile, outDir, sendTorque] = process.argv.slice(2);
const prefix = `viewtest${process.pid}`;
const bus = ['--transport', 'dds', '--prefix', prefix];
const manyBus = ['--transport', 'dds', '--prefix', `${prefix}many`];
const manyScene = join(dirname(sceneFile), 'view_many.pbtxt');
const processes = new Processes();
const start = (exe, args) => processes.start(exe, args);
const profile = mkdtempSync(join(tmpdir(), 'rigid-view-chromium-'));
const harness = browserHarness(processes, profile, 140);
const { consoleErrors, fail } = harness;
const until = (what, check, ms = 15000) => untilOr(what, check, ms);

// The large scene's checks (see the top): its own rigidd and rigid-view, a second page.
async function manyBodies() {
  const server = start(rigidd, ['--scene', manyScene, ...manyBus]);
  const view = start(rigidView, [...manyBus, '--listen', '127.0.0.1:0']);
  const url = await until('the second rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  const page = await harness.browser.newPage();
  harness.watch(page);
  await page.goto(url);
  const rv = (expr) => page.evaluate(expr);
  await until('the large scene and states', () => rv('window.rigidView.bodies.length === 300 && window.rigidView.frames > 5'), 40000);
  // Every body drawn, by one draw of impostors per shape group: sphere (with the ellipsoids), box,
  // cylinder, capsule, box of moments.
  const inst = await rv('window.rigidView.instances()');
  if (inst.path !== 'impostors' || inst.count !== 300 || inst.meshes !== 5) throw new Error(`large scene drawn as ${JSON.stringify(inst)}`);
  const reply = await page.evaluate(() => new Promise((resolve) => {
    const before = window.rigidView.replies.length;
    window.rigidView.control('pause');
    const poll = setInterval(() => {
      const r = window.rigidView.replies.slice(before).find((x) => x.op === 'pause');
      if (r) { clearInterval(poll); resolve(r); }
    }, 50);
    setTimeout(() => { clearInterval(poll); resolve(null); }, 10000);
  }));
  if (!reply || !reply.ok) throw new Error(`large scene: pause answered ${JSON.stringify(reply)}`);
  const echo = start(rigidctl, ['echo', '--csv', '--count', '1', '--timeout', '20', ...manyBus]);
  const code = await Processes.exited(echo, 25000);
  if (code !== 0) throw new Error(`rigidctl echo (large scene): ${code}: ${echo.err}`);
  const row = echo.out.split('\n').find((l) => l.split(',')[1] === 'probe');
  if (!row) throw new Error(`no probe row in rigidctl's output: ${echo.out.slice(0, 500)}`);
  const v = row.split(',').map(Number);
  const t = v[0], published = { position: v.slice(2, 5), orientation: v.slice(5, 9) };
  if (Math.abs(published.orientation[0]) > 0.999) throw new Error('the probe has not turned');
  await until(`the large scene's page to draw the state at t=${t}`,
              () => rv(`Math.abs(window.rigidView.lastState.simTime - ${t}) < 1e-9`), 5000);
  // The pose in the vertex shader's texture: float32 of the published doubles (relative 6e-8).
  const drawn = await rv('window.rigidView.renderedPose("probe")');
  const err = Math.max(...published.position.map((x, i) => Math.abs(x - drawn.position[i])),
                       ...published.orientation.map((x, i) => Math.abs(x - drawn.orientation[i])));
  console.log(`probe at t=${t}: published ${JSON.stringify(published)}, drawn ${JSON.stringify(drawn)}`);
  if (!(err < 1e-6)) throw new Error(`large scene: drawn pose differs from the published state by ${err}`);
  // Live large scenes get pose frames (protocol.hpp): velocities only for the bodies the pages
  // watch. Selecting the probe watches it: its whole published state, to the last bit.
  const unwatched = await rv('window.rigidView.bodyState("probe")');
  if (unwatched.linear_velocity !== null) throw new Error(`large scene: velocities of a body not selected: ${JSON.stringify(unwatched)}`);
  if (!(await rv('window.rigidView.select("probe")'))) throw new Error('large scene: no probe to select');
  await until('the selected probe\'s whole state', () => rv('window.rigidView.bodyState("probe").angular_velocity !== null'), 5000);
  const exact = await rv('window.rigidView.bodyState("probe")');
  const publishedAll = [...published.position, ...published.orientation, ...v.slice(9, 12), ...v.slice(12, 15)];
  const heldAll = [...exact.position, ...exact.orientation, ...exact.linear_velocity, ...exact.angular_velocity];
  if (publishedAll.some((x, i) => x !== heldAll[i])) throw new Error(`large scene: the selected probe's state ${JSON.stringify(heldAll)} is not the published ${JSON.stringify(publishedAll)}`);
  if (!(Math.hypot(...exact.angular_velocity) > 0)) throw new Error('large scene: the probe does not spin');
  const other = await rv('window.rigidView.bodies.find((b) => b.name !== "probe").name');
  if ((await rv(`window.rigidView.bodyState(${JSON.stringify(other)})`)).linear_velocity !== null) throw new Error(`large scene: ${other} has velocities though not selected`);
  const panel = await page.textContent('#selw');
  if (panel === '–' || !panel) throw new Error(`large scene: the body panel's angular velocity: ${panel}`);
  await rv('window.rigidView.select(null)');
  await until('the probe\'s velocities gone once unselected', () => rv('window.rigidView.bodyState("probe").linear_velocity === null'), 5000);
  // A --read-only rigid-view on the same bus, from a plain WebSocket: pause refused with the
  // reason, watch allowed (it only changes what this connection sees), and the pose frame read
  // here independently of the page: 32 B a body, then the watched probe's record with the
  // published doubles.
  const readOnly = start(rigidView, [...manyBus, '--listen', '127.0.0.1:0', '--read-only']);
  const roUrl = await until('the read-only rigid-view to print its URL',
                            () => (readOnly.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  const roPage = await harness.browser.newPage();
  harness.watch(roPage);
  await roPage.goto(roUrl);
  const probeId = await rv('window.rigidView.bodyState("probe").id');
  const ro = await roPage.evaluate((id) => new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.binaryType = 'arraybuffer';
    const out = { pause: null, errors: [], record: null };
    ws.onopen = () => {
      ws.send('{"op":"pause","id":5}');
      ws.send(JSON.stringify({ op: 'watch', body: id }));
    };
    ws.onmessage = (e) => {
      if (typeof e.data === 'string') {
        const m = JSON.parse(e.data);
        if (m.type === 'reply' && m.op === 'pause') out.pause = m;
        if (m.type === 'error') out.errors.push(m.message);
        return;
      }
      ws.send('{"op":"ack"}');
      const v = new DataView(e.data), n = v.getUint32(4, true), flags = v.getUint32(12, true);
      const end = 40 + 32 * n + 24, k = v.getUint32(end - 8, true);
      if (e.data.byteLength !== end + 120 * k) { out.record = { badLength: e.data.byteLength, n, k }; return; }
      for (let r = 0; r < k; ++r) {
        const slot = v.getInt32(end + 120 * r, true);
        if (v.getInt32(40 + 28 * n + 4 * slot, true) !== id) continue;
        const x = Array.from({ length: 13 }, (_, c) => v.getFloat64(end + 120 * r + 16 + 8 * c, true));
        out.record = { flags, n, sim_time: v.getFloat64(24, true), x };
      }
      if (out.record && out.pause) { ws.close(); resolve(out); }
    };
    setTimeout(() => { ws.close(); resolve(out); }, 8000);
  }), probeId);
  if (!ro.pause || ro.pause.ok || ro.pause.message !== 'rigid-view runs --read-only') throw new Error(`read-only rigid-view answered pause with ${JSON.stringify(ro.pause)}`);
  if (ro.errors.length) throw new Error(`read-only rigid-view refused: ${ro.errors}`);
  if (!ro.record || ro.record.badLength || ro.record.flags !== 2 || ro.record.n !== 300) throw new Error(`no pose frame with the watched probe: ${JSON.stringify(ro.record)}`);
  // (Paused since the echo: the same state.)
  if (ro.record.x.some((x, i) => x !== publishedAll[i])) throw new Error(`the watched probe's record ${JSON.stringify(ro.record.x)} is not the published ${JSON.stringify(publishedAll)}`);
  await roPage.close();
  readOnly.kill('SIGTERM');
  // On the screen: the probe's colour (the palette's first, light blue 0x4fc3f7, shaded) where its
  // published centre projects, and not 0.5 m above it (its half diagonal is 0.29 m; behind that
  // spot are only the background and the grid, both grey).
  const at = await rv('window.rigidView.screenOf("probe")');
  const above = await rv('window.rigidView.screenOf("probe", [0, 0, 0.5])');
  for (const p of [at, above]) {
    const under = await rv(`document.elementFromPoint(${p.x}, ${p.y}).tagName`);
    if (under !== 'CANVAS') throw new Error(`large scene: the ${under} at ${JSON.stringify(p)} hides the probe`);
  }
  // The canvas's colours (RGBA) at points of the page (CSS px), all from one frame.
  const pixels = (points) => page.evaluate((pts) => new Promise((resolve) => requestAnimationFrame(() => {
    const canvas = document.querySelector('#view canvas');
    const r = canvas.getBoundingClientRect();
    const c = document.createElement('canvas');
    c.width = canvas.width;
    c.height = canvas.height;
    const g = c.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const s = canvas.width / r.width;
    resolve(pts.map(([px, py]) => Array.from(g.getImageData(Math.round((px - r.left) * s), Math.round((py - r.top) * s), 1, 1).data)));
  })), points);
  const [probe, empty] = await pixels([[at.x, at.y], [above.x, above.y]]);
  console.log(`large scene: pixel at the probe ${probe}, 0.5 m above it ${empty}`);
  if (!(probe[2] > probe[0] + 40 && probe[1] > probe[0] + 20)) throw new Error(`not the probe's colour where it is drawn: ${probe}`);
  if (!(Math.abs(empty[2] - empty[0]) < 20 && Math.abs(empty[1] - empty[0]) < 20))
    throw new Error(`colour where no body is (0.5 m above the probe): ${empty}`);
  // The impostor draws the probe's true box, not the quad around it: on a grid of points around
  // its centre, the pixel has the probe's colour exactly where the page's exact ray cast on the CPU
  // (pickBodies: the box in B) hits the probe, and not where it hits nothing (background, grid or
  // world axes there). Points within kEdge CSS px of an edge (where a neighbour's answer differs;
  // two rendered pixels more at a lower render scale) are skipped, as are points where the ray hits
  // another body.
  // The scene is paused: the points the page's ray cast labels and the pixels are of one pose.
  // The render scale is held at 1 meanwhile (full resolution, as the page drew this scene before
  // its dynamic resolution aimed at every refresh; at lower scales, CI once found 1 point of
  // ~1700 wrong, at the grid's edge, not reproduced in 4 local runs at 0.25-0.43), and a frame
  // drawn at it first.
  await rv('window.rigidView.holdRenderScale(1)');
  const heldFrom = await rv('window.rigidView.rendered');
  await until('a frame at the held render scale', () => rv(`window.rigidView.rendered >= ${heldFrom + 2}`), 3000);
  const grid = await page.evaluate(([cx, cy]) => {
    const kEdge = Math.ceil(2 + 2 / window.rigidView.renderScale()), kStep = 2, kReach = 80;
    const points = [];
    for (let y = cy - kReach; y <= cy + kReach; y += kStep) {
      for (let x = cx - kReach; x <= cx + kReach; x += kStep) {
        const at = window.rigidView.bodyAt(x, y);
        if (at !== 'probe' && at !== null) continue;
        const around = [[kEdge, 0], [-kEdge, 0], [0, kEdge], [0, -kEdge], [kEdge, kEdge], [-kEdge, -kEdge],
                        [kEdge, -kEdge], [-kEdge, kEdge]];
        if (around.some(([dx, dy]) => window.rigidView.bodyAt(x + dx, y + dy) !== at)) continue;
        points.push({ x, y, at });
      }
    }
    return points;
  }, [at.x, at.y]);
  const colours = await pixels(grid.map((p) => [p.x, p.y]));
  // The probe's light blue, lit or in shade (its red more than a seventh of its blue; the world's
  // z axis, light blue too, has none).
  const probeColour = ([pr, pg, pb]) => pb > pr + 25 && pg > pr + 10 && pr > 0.15 * pb;
  const silhouette = { probe: 0, empty: 0, wrong: [] };
  grid.forEach((p, k) => {
    const [pr, pg, pb] = colours[k];
    if (probeColour(colours[k]) !== (p.at === 'probe')) silhouette.wrong.push({ ...p, pixel: [pr, pg, pb] });
    silhouette[p.at === 'probe' ? 'probe' : 'empty'] += 1;
  });
  console.log(`large scene: probe silhouette at render scale ${await rv('window.rigidView.renderScale()')}: ${silhouette.probe} points on the probe, ${silhouette.empty} around it, ${silhouette.wrong.length} wrong`);
  if (silhouette.probe < 20 || silhouette.empty < 20) throw new Error(`too few points checked around the probe: ${JSON.stringify(silhouette)}`);
  if (silhouette.wrong.length) throw new Error(`the probe's drawn silhouette differs from its box: ${JSON.stringify(silhouette.wrong.slice(0, 10))}`);
  // The quad is large enough: where the grid is coarsest, at the silhouette's corners (what a quad
  // too small cuts first), the pixels 4 CSS px inside each corner of the box as drawn (its 8
  // vertices, from the drawn pose, projected), towards the centre, are the probe's where the CPU
  // ray cast says so (also 1 px around: no edge within reach).
  const corners = await page.evaluate(async () => {
    const THREE = await import('three');  // (the page's import map)
    const [w, x, y, z] = window.rigidView.renderedPose('probe').orientation;
    const q_WB = new THREE.Quaternion(x, y, z, w);
    const c = window.rigidView.screenOf('probe');
    const points = [];
    for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1]) {
      const p_BoC_W = new THREE.Vector3(0.2 * sx, 0.15 * sy, 0.15 * sz).applyQuaternion(q_WB);
      const v = window.rigidView.screenOf('probe', p_BoC_W.toArray());
      const dx = c.x - v.x, dy = c.y - v.y, len = Math.hypot(dx, dy);
      const p = { x: v.x + (4 * dx) / len, y: v.y + (4 * dy) / len };
      const around = [[0, 0], [1, 0], [-1, 0], [0, 1], [0, -1]];
      if (around.every(([ax, ay]) => window.rigidView.bodyAt(p.x + ax, p.y + ay) === 'probe')) points.push(p);
    }
    return points;
  });
  const cornerColours = await pixels(corners.map((p) => [p.x, p.y]));
  const cutOff = corners.filter((p, k) => !probeColour(cornerColours[k]));
  console.log(`large scene: ${corners.length} points inside the probe's drawn corners, ${cutOff.length} not drawn`);
  if (corners.length < 4) throw new Error(`too few points inside the probe's corners: ${JSON.stringify(corners)}`);
  if (cutOff.length) throw new Error(`the probe's impostor cuts off its corners at ${JSON.stringify(cutOff)}`);
  await rv('window.rigidView.holdRenderScale(null)');
  // Picking without instanced meshes (the bodies' own shapes from the poses): hover the probe.
  await page.mouse.move(at.x, at.y);
  await until('the probe under the pointer in the large scene', () => rv('window.rigidView.hovered() === "probe"'), 3000);
  await page.close();
  view.kill('SIGTERM');
  server.kill('SIGTERM');
  await Promise.race([Promise.all([view.done, server.done]), sleep(5000)]);
}

try {
  const server = start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = start(rigidView, [...bus, '--listen', '127.0.0.1:0']);
  const url = await until('rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  console.log(`rigid-view at ${url}`);

  harness.browser = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium', headless: true, chromiumSandbox: false,
    viewport: { width: 1000, height: 700 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = harness.browser.pages()[0] || await harness.browser.newPage();
  harness.watch(page);
  await page.goto(url);

  const rv = (expr) => page.evaluate(expr);
  // The scene's bodies, each with its shape, and states arriving.
  await until('the scene and states', () => rv('window.rigidView.bodies.length === 6 && window.rigidView.frames > 5'), 40000)
    .catch(async (e) => { throw new Error(`${e.message}: page has ${await rv('JSON.stringify({connected: window.rigidView.connected, bodies: window.rigidView.bodies.length, frames: window.rigidView.frames})').catch((x) => String(x))}`); });
  const shapes = await rv('Object.fromEntries(window.rigidView.bodies.map((b) => [b.name, b.shape + (b.fromMoments ? "*" : "")]))');
  const want = { spinner: 'box', ball: 'sphere', can: 'cylinder', pill: 'capsule', egg: 'ellipsoid', lump: 'box*' };
  if (JSON.stringify(shapes) !== JSON.stringify(want)) throw new Error(`bodies drawn: ${JSON.stringify(shapes)}`);
  // Framed at the first state: the camera aims at the centre of the bodies' bounds (x and y from -1
  // to 1, z from 0 to 1: the centre (0, 0, 0.5)) and every body is on the screen.
  const target = await rv('window.rigidView.target()');
  if (Math.max(...target.map((x, i) => Math.abs(x - [0, 0, 0.5][i]))) > 1e-9) throw new Error(`the camera aims at ${target}, not the scene's centre`);
  const onScreen = await rv('window.rigidView.bodies.map((b) => { const s = window.rigidView.screenOf(b.name); return s.x > 0 && s.x < innerWidth && s.y > 0 && s.y < innerHeight; })');
  if (!onScreen.every((x) => x)) throw new Error(`bodies off the screen after framing: ${onScreen}`);
  // Instancing: every body of the scene is an instance; bodies of one shape share a mesh whatever
  // their sizes (the ball and the egg: the unit sphere, scaled), the translucent box of moments
  // apart from the solid box: 5 meshes for 6 bodies.
  const inst = await rv('window.rigidView.instances()');
  if (inst.count !== 6 || inst.meshes !== 5) throw new Error(`instances: ${JSON.stringify(inst)}`);
  // WebGL on the CPU here (SwiftShader): the page knows it and draws even a small scene without
  // multisampling, which a software renderer pays per pixel (bench/notes/view-bench.md).
  const gl = await rv('({ software: window.rigidView.softwareGL, antialias: window.rigidView.antialias() })');
  if (gl.software !== true || gl.antialias !== false) throw new Error(`in SwiftShader the page has ${JSON.stringify(gl)} (expected software and no multisampling)`);
  // States reach the drawing at most about 60 times a second although rigidd publishes 200:
  // rigid-view sends at most 60 a second, and the page applies at most one per animation frame.
  // Counted on the page's own clock (fewer than 75 a second), which a stall of this test's
  // process cannot stretch. From below only states flowing is asked (at least 5 a second): the
  // page draws as fast as the machine lets it, and how fast is bench/view's question, not a
  // test's.
  const [f0, t0] = await rv('[window.rigidView.frames, performance.now()]');
  await sleep(1000);
  const [f1, t1] = await rv('[window.rigidView.frames, performance.now()]');
  const rate = (f1 - f0) / ((t1 - t0) / 1000);
  if (rate < 5 || rate > 75) throw new Error(`${rate.toFixed(1)} states applied a second by the page's clock (expected 5 to 75: rigid-view sends at most 60)`);
  // Energy and angular momentum (about the CoM, in W) of the torque-free spinner are conserved
  // to the integrator's accuracy: computed by rigid-view from the published state (w_WB in W,
  // the inertia in B from SceneInfo), a frame mix-up would show as a drift of order 1.
  const spinDrift = await until('drift samples', () => rv('window.rigidView.drift("spinner")'));
  if (!(spinDrift.energy < 1e-6 && spinDrift.momentum < 1e-6)) throw new Error(`spinner drift: ${JSON.stringify(spinDrift)}`);
  // (rigid-view's formulas on a case worked by hand: view_drift_test.) DriftTable.worst names the
  // body with the largest drift (the page's label "all bodies (max: NAME)"), from the frame's
  // drifts by state slot: body 1 of 3 has the largest energy drift, body 2 the largest momentum's.
  const worst = await page.evaluate(async () => {
    const { DriftTable } = await import('/drift.js');
    const d = new DriftTable();
    d.setBodies(3);
    d.update(3, [2, 0, 1], new Float32Array([1e-3, 0, 3]), new Float32Array([5e-2, 1e-9, 0]));
    return [d.worst(), d.worst(0)];
  });
  if (worst[0].energyAt !== 1 || worst[0].momentumAt !== 2 || worst[0].energy !== 3 ||
      worst[1].energy !== 0 || !(Math.abs(worst[1].momentum - 1e-9) < 1e-15))
    throw new Error(`DriftTable.worst: ${JSON.stringify(worst)}`);
  const a = await rv('window.rigidView.renderedPose("spinner")');
  await sleep(200);
  const b = await rv('window.rigidView.renderedPose("spinner")');
  if (JSON.stringify(a.orientation) === JSON.stringify(b.orientation)) throw new Error('the spinner does not turn');

  async function press(button, op) {
    const before = await rv('window.rigidView.replies.length');
    await page.click(`#${button}`);
    const reply = await until(`rigidd's answer to ${op}`, () => rv(`window.rigidView.replies.slice(${before}).find((r) => r.op === "${op}")`));
    if (!reply.ok) throw new Error(`${op} answered ${JSON.stringify(reply)}`);
    const shown = await page.textContent('#answer');
    if (!shown.startsWith(`${op}: ok at tick`)) throw new Error(`${op}: the page shows '${shown}'`);
    return reply;
  }
  await press('pause', 'pause');

  // The drawn pose against the state rigidd publishes, read by an independent subscriber.
  // While paused, the state rigidd publishes (read by rigidctl echo, an independent subscriber)
  // and the pose drawn for the spinner must be the same numbers.
  const echo = start(rigidctl, ['echo', '--csv', '--count', '1', '--timeout', '20', ...bus]);
  const code = await Processes.exited(echo, 25000);
  if (code !== 0) throw new Error(`rigidctl echo: ${code}: ${echo.err}`);
  const row = echo.out.split('\n').find((l) => l.split(',')[1] === 'spinner');
  if (!row) throw new Error(`no spinner row in rigidctl's output: ${echo.out}`);
  const v = row.split(',').map(Number);
  const t = v[0], published = { position: v.slice(2, 5), orientation: v.slice(5, 9) };
  await until(`the page to draw the state at t=${t}`,
              () => rv(`Math.abs(window.rigidView.lastState.simTime - ${t}) < 1e-9`), 5000);
  const drawn = await rv('window.rigidView.renderedPose("spinner")');
  const held = await rv('window.rigidView.bodyState("spinner")');
  const velocities = { linear: v.slice(9, 12), angular: v.slice(12, 15) };
  const err = Math.max(...published.position.map((x, i) => Math.abs(x - drawn.position[i])),
                       ...published.orientation.map((x, i) => Math.abs(x - drawn.orientation[i])),
                       ...velocities.linear.map((x, i) => Math.abs(x - held.linear_velocity[i])),
                       ...velocities.angular.map((x, i) => Math.abs(x - held.angular_velocity[i])));
  if (Math.hypot(...velocities.angular) < 1) throw new Error(`the spinner's angular velocity: ${velocities.angular}`);
  console.log(`spinner at t=${t}: published ${JSON.stringify(published)}, drawn ${JSON.stringify(drawn)}`);
  if (!(err < 1e-9)) throw new Error(`drawn pose differs from the published state by ${err}`);
  if (Math.abs(published.orientation[0]) > 0.999) throw new Error('the spinner has not turned');

  // Draw on change (clients/view/web/redraw.js): paused, with the pointer and the camera still,
  // the page draws a frame a second (its heartbeat), although rigidd still publishes (the same
  // poses), and its animation loop stops in between (a few callbacks a second, not 60), while
  // every state is still acknowledged; a turn of the mouse wheel over the view (a zoom) is drawn.
  // (The plots' canvases too are redrawn only when they get a sample: plotDraws against plots.)
  const frameCounts = async () => {
    const [drawn, skipped, plotDraws, plots] = await rv('[window.rigidView.rendered, window.rigidView.skipped, window.rigidView.plotDraws(), window.rigidView.plots()]');
    return { drawn, skipped, plotDraws: plotDraws.drift + plotDraws.lateness, samples: plots.drift + plots.lateness };
  };
  await sleep(600);  // past the linger of the last input (the click on pause)
  const idle0 = await frameCounts(), statesIdle0 = await rv('window.rigidView.frames');
  await sleep(2500);
  const idle1 = await frameCounts(), statesIdle1 = await rv('window.rigidView.frames');
  const idle = { drawn: idle1.drawn - idle0.drawn, skipped: idle1.skipped - idle0.skipped,
                 states: statesIdle1 - statesIdle0, plotDraws: idle1.plotDraws - idle0.plotDraws,
                 plotSamples: idle1.samples - idle0.samples };
  console.log(`paused, still: ${idle.drawn} frames drawn, ${idle.skipped} skipped, ${idle.states} states applied, plots redrawn ${idle.plotDraws} times for ${idle.plotSamples} samples in 2.5 s`);
  if (idle.states < 2) throw new Error(`paused: rigidd's states stopped reaching the page: ${JSON.stringify(idle)}`);
  if (idle.drawn > 4 || idle.drawn + idle.skipped > 30) throw new Error(`paused and still, the page drew ${JSON.stringify(idle)} (expected a heartbeat a second and its loop stopped in between)`);
  const unacknowledged = await rv('window.rigidView.unacknowledged()');
  if (unacknowledged > 1) throw new Error(`paused: ${unacknowledged} states not acknowledged`);
  if (idle.plotDraws > idle.plotSamples + 2) throw new Error(`the plots were redrawn more often than they got samples: ${JSON.stringify(idle)}`);
  const camera0 = await rv('window.rigidView.cameraPosition()');
  const viewCentre = await rv('(() => { const r = document.querySelector("#view canvas").getBoundingClientRect(); return { x: r.left + r.width / 2, y: r.top + r.height / 2 }; })()');
  await page.mouse.move(viewCentre.x, viewCentre.y);
  await page.mouse.wheel(0, -200);
  await until('frames drawn for the zoom', async () => (await frameCounts()).drawn >= idle1.drawn + 3, 5000);
  const camera1 = await rv('window.rigidView.cameraPosition()');
  if (camera1.every((x, i) => x === camera0[i])) throw new Error(`the wheel did not move the camera: ${camera0}`);

  const stepReply = await press('step', 'step');
  await until('the page to draw the stepped state',
              () => rv(`window.rigidView.lastState.tick === ${stepReply.tick}`), 5000);
  const reset = await press('reset', 'reset');
  if (reset.tick !== 0) throw new Error(`reset answered at tick ${reset.tick}`);
  await press('resume', 'resume');
  // Moving again, every frame is drawn (each state's poses differ from the last's).
  await sleep(300);
  const moving0 = await frameCounts();
  await sleep(1500);
  const moving1 = await frameCounts();
  const moving = { drawn: moving1.drawn - moving0.drawn, skipped: moving1.skipped - moving0.skipped };
  console.log(`running: ${moving.drawn} frames drawn, ${moving.skipped} skipped in 1.5 s`);
  if (moving.drawn < 10 || moving.skipped > moving.drawn / 4) throw new Error(`running, the page drew ${JSON.stringify(moving)} (expected every frame)`);

  // Looks (pixels read from the canvas, at full render scale). The world axes show over the grid
  // they lie in: the pixels halfway along x and y are red and green (depth-tested against the
  // grid's lines they flickered in and out). The ball (at rest, unturned after the reset) is
  // darker on alternate octants of its frame: two points of its surface on either side of its
  // y-z plane, lit nearly alike, differ in brightness by about the markings' factor.
  await rv('window.rigidView.holdRenderScale(1)');
  const heldAt = await rv('window.rigidView.rendered');
  await until('a frame at full render scale', () => rv(`window.rigidView.rendered >= ${heldAt + 2}`), 3000);
  const pixelsAt = (points) => page.evaluate((pts) => new Promise((resolve) => requestAnimationFrame(() => {
    const canvas = document.querySelector('#view canvas');
    const r = canvas.getBoundingClientRect();
    const c = document.createElement('canvas');
    c.width = canvas.width;
    c.height = canvas.height;
    const g = c.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const s = canvas.width / r.width;
    resolve(pts.map(({ x, y }) => Array.from(g.getImageData(Math.round((x - r.left) * s), Math.round((y - r.top) * s), 1, 1).data)));
  })), points);
  const [xAxis, yAxis] = await pixelsAt([await rv('window.rigidView.screenAt([0.45, 0, 0])'),
                                         await rv('window.rigidView.screenAt([0, 0.45, 0])')]);
  console.log(`world axes over the grid: x ${xAxis}, y ${yAxis}`);
  if (!(xAxis[0] > 150 && xAxis[1] < 110 && xAxis[2] < 110)) throw new Error(`the x axis is not drawn over the grid: ${xAxis}`);
  if (!(yAxis[1] > 100 && yAxis[0] < 100 && yAxis[2] < 110)) throw new Error(`the y axis is not drawn over the grid: ${yAxis}`);
  const ballRadius = 0.15;
  // Points of its surface (not inside it: a point inside is drawn where the ray to it meets the
  // surface, on the camera's side, which may be across that plane), facing the camera.
  const side = (sx) => { const n = Math.hypot(0.3, 1, 1); return [sx * 0.3, -1, 1].map((c) => ballRadius * c / n); };
  const [light, dark] = await pixelsAt([await rv(`window.rigidView.screenOf("ball", ${JSON.stringify(side(-1))})`),
                                        await rv(`window.rigidView.screenOf("ball", ${JSON.stringify(side(1))})`)]);
  const luma = ([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b;
  // (The sun lights the darker octant's point more: unmarked, it is the brighter of the two.)
  const ratio = luma(dark) / luma(light);
  console.log(`the ball's octants: ${light} and ${dark} (brightness ratio ${ratio.toFixed(3)})`);
  if (!(ratio > 0.5 && ratio < 0.9)) throw new Error(`the ball shows no markings: ${light} and ${dark}`);
  await rv('window.rigidView.holdRenderScale(null)');
  // Names: the body under the pointer is named beside it; "names" (the key N) names every body; the
  // help (the key ?) lists the mouse and keys, and Esc closes it; "fit" (the key F) frames the
  // scene again after the camera moved away.
  const canAt = await rv('window.rigidView.screenOf("can")');
  await page.mouse.move(canAt.x, canAt.y);
  const canId = await rv('window.rigidView.bodyState("can").id');
  await until('the can named under the pointer', () => rv(`window.rigidView.tooltip === "can (id ${canId})"`), 3000);
  await page.mouse.move(500, (await rv('innerHeight')) - 5);  // off the bodies, on the view
  await page.keyboard.press('n');
  const named = await until('every body named', () => rv('window.rigidView.labels().length === 6 ? window.rigidView.labels() : null'), 3000);
  if ([...named].sort().join() !== 'ball,can,egg,lump,pill,spinner') throw new Error(`names shown: ${named}`);
  await page.keyboard.press('n');
  await until('the names gone', () => rv('window.rigidView.labels().length === 0'), 3000);
  await page.keyboard.press('?');
  if (!(await rv('window.rigidView.helpShown'))) throw new Error('the key ? did not show the help');
  const help = await page.textContent('#help-table');
  if (!/left drag on a body/.test(help) || !/zoom to fit/.test(help)) throw new Error(`the help lists: ${help}`);
  await page.keyboard.press('Escape');
  if (await rv('window.rigidView.helpShown')) throw new Error('Esc did not close the help');
  const distance = '(() => { const t = window.rigidView.target(), c = window.rigidView.cameraPosition(); return Math.hypot(c[0] - t[0], c[1] - t[1], c[2] - t[2]); })()';
  const near = await rv(distance);
  await page.mouse.move(canAt.x, canAt.y);
  await page.mouse.wheel(0, 1500);  // far out
  await until('the camera zoomed out', async () => (await rv(distance)) > 1.5 * near, 3000);
  await page.keyboard.press('f');
  const refit = await until('the scene framed again', () => rv(`(() => { const t = window.rigidView.target(), d = ${distance}; return Math.hypot(t[0], t[1], t[2] - 0.5) < 1e-9 && d < ${1.5 * near} ? d : null; })()`), 3000);
  console.log(`framed again: camera ${refit.toFixed(3)} m from the scene's centre (${near.toFixed(3)} before zooming out)`);

  // Push with the mouse: drag the ball (at rest after the reset, no gravity) to the right on the
  // screen and hold it there. The pull is a critically damped spring to the pointer: the ball,
  // read by rigidctl, has moved right on the screen and is nearly at rest when let go (it does
  // not fly away), and an arrow is drawn for the push while the button is held, never shorter
  // than a few percent of its distance from the camera; after release the velocity stays
  // constant.
  async function echoBody(name) {
    const e = start(rigidctl, ['echo', '--csv', '--count', '1', '--timeout', '10', ...bus]);
    const c = await Processes.exited(e, 15000);
    if (c !== 0) throw new Error(`rigidctl echo: ${c}: ${e.err}`);
    const r = e.out.split('\n').find((l) => l.split(',')[1] === name);
    if (!r) throw new Error(`no ${name} row in rigidctl's output: ${e.out}`);
    const x = r.split(',').map(Number);
    return { t: x[0], p: x.slice(2, 5), v: x.slice(9, 12) };
  }
  const ballBefore = await echoBody('ball');
  if (Math.hypot(...ballBefore.v) > 1e-12) throw new Error(`the ball moves before the push: ${ballBefore.v}`);
  const at = await rv('window.rigidView.screenOf("ball")');
  const onCanvas = await rv(`document.elementFromPoint(${at.x}, ${at.y}).tagName`);
  if (onCanvas !== 'CANVAS') throw new Error(`the ball is under the ${onCanvas} at ${JSON.stringify(at)}`);
  const pushesBefore = await rv('window.rigidView.pushes');
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  await page.mouse.move(at.x + 60, at.y, { steps: 5 });
  await page.mouse.move(at.x + 120, at.y, { steps: 5 });
  const ballId = await rv('window.rigidView.bodyState("ball").id');
  const arrow = await until('a wrench arrow on the ball while pushing',
                            () => rv(`window.rigidView.arrows.find((a) => a.body === ${ballId})`), 5000);
  if (!(arrow.force[0] ** 2 + arrow.force[1] ** 2 + arrow.force[2] ** 2 > 1)) throw new Error(`arrow ${JSON.stringify(arrow)}`);
  const eye = await rv('window.rigidView.cameraPosition()');
  const arrowDistance = Math.hypot(...arrow.from.map((x, i) => x - eye[i]));
  if (!(arrow.length >= 0.06 * arrowDistance - 1e-9)) throw new Error(`the arrow is ${arrow.length} m long, ${arrowDistance} m from the camera`);
  await sleep(2500);  // the spring settles (its time constant is 1/4 s)
  const settledPull = await rv('window.rigidView.pullForce');
  await page.mouse.up();
  const pushes = (await rv('window.rigidView.pushes')) - pushesBefore;
  if (pushes < 5) throw new Error(`${pushes} pushes sent while dragging`);
  await until('the arrow to go after release',
              () => rv(`!window.rigidView.arrows.some((a) => a.body === ${ballId})`), 5000);
  await sleep(300);  // past the push's 0.1 s ttl
  const ball1 = await echoBody('ball');
  await sleep(500);
  const ball2 = await echoBody('ball');
  const speed = Math.hypot(...ball1.v);
  const moved = ball1.p.map((x, i) => x - ballBefore.p[i]);
  console.log(`ball after the drag: moved ${JSON.stringify(moved)}, v ${JSON.stringify(ball1.v)} (${pushes} pushes, pull ${JSON.stringify(settledPull)} N when let go), then ${JSON.stringify(ball2.v)}`);
  if (!(Math.hypot(...moved) > 0.2)) throw new Error(`the drag did not move the ball: it moved ${moved}`);
  if (!(speed < 0.05)) throw new Error(`the ball flies away after the drag: v = ${ball1.v}`);
  // The direction on the screen: where the ball went relative to where it was.
  const p0 = await rv(`window.rigidView.screenAt(${JSON.stringify(ballBefore.p)})`);
  const p1 = await rv(`window.rigidView.screenAt(${JSON.stringify(ball1.p)})`);
  const dx = p1.x - p0.x, dy = p1.y - p0.y;
  if (!(dx > 0 && Math.abs(dy) < 0.5 * dx)) throw new Error(`the ball moved along (${dx}, ${dy}) on the screen, not to the right`);
  if (!(ball2.t > ball1.t) || Math.max(...ball1.v.map((x, i) => Math.abs(x - ball2.v[i]))) > 1e-9)
    throw new Error(`the push did not stop after release: v ${ball1.v} at ${ball1.t}, ${ball2.v} at ${ball2.t}`);
  // The push's work is not drift: the ball's reference is taken again after it ends.
  const ballDrift = await rv('window.rigidView.drift("ball")');
  if (!(ballDrift.energy < 1e-6 && ballDrift.momentum < 1e-6)) throw new Error(`ball drift after the push: ${JSON.stringify(ballDrift)}`);

  // rigidd's edits from the page: the selected ball's state set from the form (a velocity up z),
  // then "put back" (the key B): its scene state again, at rest at (1, 0, 0); each answered by
  // rigidd with its tick, and neither is drift (the reference is taken again).
  if (!(await rv('window.rigidView.select("ball")'))) throw new Error('no ball to select');
  await page.click('#setstate summary');
  await page.fill('#edit-v', '0, 0, 0.5');
  await page.fill('#edit-w', '');
  const setBefore = await rv('window.rigidView.replies.length');
  await page.click('#edit-set');
  const setReply = await until('rigidd\'s answer to set_state', () => rv(`window.rigidView.replies.slice(${setBefore}).find((r) => r.op === "set_state")`));
  if (!setReply.ok) throw new Error(`set_state answered ${JSON.stringify(setReply)}`);
  await until('the ball rising at 0.5 m/s', () => rv('(() => { const v = window.rigidView.bodyState("ball").linear_velocity; return v[2] === 0.5 && v[0] === 0 && v[1] === 0; })()'), 5000);
  const backBefore = await rv('window.rigidView.replies.length');
  await page.keyboard.press('b');
  const backReply = await until('rigidd\'s answer to reset_body', () => rv(`window.rigidView.replies.slice(${backBefore}).find((r) => r.op === "reset_body")`));
  if (!backReply.ok || !(backReply.tick > setReply.tick)) throw new Error(`reset_body answered ${JSON.stringify(backReply)} after set_state at ${setReply.tick}`);
  if (!(await page.textContent('#answer')).startsWith('reset_body: ok at tick')) throw new Error(`the page shows '${await page.textContent('#answer')}'`);
  await until('the ball put back', () => rv('(() => { const s = window.rigidView.bodyState("ball"); return s.position.join() === "1,0,0" && s.linear_velocity.join() === "0,0,0"; })()'), 5000);
  const backDrift = await until('drift after the edits', () => rv('window.rigidView.drift("ball")'));
  if (!(backDrift.energy < 1e-6 && backDrift.momentum < 1e-6)) throw new Error(`ball drift after the edits: ${JSON.stringify(backDrift)}`);
  await rv('window.rigidView.select(null)');

  // A pure torque, given in the spinner's frame B (rigidd turns it by R_WB when it applies it):
  // the page must draw a circular arrow about tau_W = R_WB tau_B through p_WBo, turning by the
  // right-hand rule, and no force arrow. 1 s at 200 Hz: it acts on the steps from its tick k for
  // 200 ticks, so it is drawn with the states k+1 .. k+200 and then gone.
  const tauB = [0.3, -0.1, 0.2];
  const ttl = 1;
  const torqueTicks = 200;  // rigidd's ticks_to_live(1 s, 5 ms)
  const sender = start(sendTorque, [prefix, 'spinner', tauB.join(','), 'body', String(ttl)]);
  const sent = await Promise.race([sender.done, sleep(15000).then(() => 'timeout')]);
  if (sent !== 0) throw new Error(`view_send_torque: ${sent}: ${sender.err}`);
  const k = Number((sender.out.match(/accepted at tick (\d+)/) || [])[1]);
  if (!Number.isInteger(k)) throw new Error(`view_send_torque printed ${sender.out}`);
  const spinnerId = await rv('window.rigidView.bodyState("spinner").id');
  // Read in an animation frame after the page's own (which drew the arrows): the arrow and the
  // state it was drawn with, with no message handled in between.
  const inFrame = () => page.evaluate((id) => new Promise((resolve) => requestAnimationFrame(() => {
    const v = window.rigidView;
    resolve({ torque: v.torques.find((x) => x.body === id) || null,
              force: v.arrows.find((x) => x.body === id) || null,
              state: v.bodyState('spinner'), tick: v.lastState.tick });
  })), spinnerId);
  const seen = await until('a torque arrow on the spinner', async () => {
    const f = await inFrame();
    return f.torque ? f : null;
  }, 5000);
  if (!(seen.tick > k && seen.tick <= k + torqueTicks)) throw new Error(`torque arrow drawn with tick ${seen.tick}, accepted at ${k}`);
  if (seen.force) throw new Error(`a force arrow for a pure torque: ${JSON.stringify(seen.force)}`);
  {
    // tau_W = R_WB tau_B with q_WB = (w, x, y, z): v + 2 q_v x (q_v x v + w v).
    const [w, x, y, z] = seen.state.orientation;
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const qv = [x, y, z];
    const t1 = cross(qv, tauB).map((c, i) => c + w * tauB[i]);
    const tauW = cross(qv, t1).map((c, i) => tauB[i] + 2 * c);
    const norm = Math.hypot(...tauW);
    const axis = tauW.map((c) => c / norm);
    const t = seen.torque;
    const diff = (a, b) => Math.max(...a.map((c, i) => Math.abs(c - b[i])));
    console.log(`torque arrow at tick ${seen.tick} (accepted at ${k}): tau_W ${JSON.stringify(tauW)}, drawn ${JSON.stringify(t)}`);
    // (A BODY-frame torque drawn unrotated would be off by the spinner's turn since the reset.)
    if (diff(t.axis, axis) > 1e-9 || diff(t.torque, tauW) > 1e-9) throw new Error(`torque axis ${t.axis}, want ${axis}`);
    if (diff(t.center, seen.state.position) > 1e-12) throw new Error(`torque arrow about ${t.center}, the body is at ${seen.state.position}`);
    // The cone at the arc's end: on the circle of the arc's radius in the plane perpendicular to
    // the axis, pointing along the circle so that (tip - centre) x direction is along +axis.
    const r = t.tip.map((c, i) => c - t.center[i]);
    if (Math.abs(Math.hypot(...r) - t.radius) > 1e-9 || Math.abs(dot(r, axis)) > 1e-9 ||
        Math.abs(dot(t.tipDirection, r)) > 1e-9)
      throw new Error(`the cone is not on the arc: ${JSON.stringify(t)}`);
    const sense = dot(cross(r, t.tipDirection), axis) / t.radius;
    if (!(sense > 0.999)) throw new Error(`the torque arrow turns the wrong way: (r x d).axis = ${sense}`);
    if (!(t.radius >= 0.1)) throw new Error(`torque arrow radius ${t.radius}`);
  }
  // Gone exactly after the ttl: the last frame drawing it shows a tick <= k + 200, the first
  // frame without it a tick > k + 200 (frames polled one by one on the page).
  const expiry = await page.evaluate((id) => new Promise((resolve) => {
    let lastWith = -1;
    const poll = () => {
      const v = window.rigidView;
      if (v.torques.some((x) => x.body === id)) {
        lastWith = v.lastState.tick;
        requestAnimationFrame(poll);
      } else {
        resolve({ lastWith, firstWithout: v.lastState.tick });
      }
    };
    requestAnimationFrame(poll);
    setTimeout(() => resolve(null), 8000);
  }), spinnerId);
  console.log(`torque arrow: accepted at tick ${k}, last drawn with tick ${expiry && expiry.lastWith}, gone at ${expiry && expiry.firstWithout}`);
  if (!expiry) throw new Error('the torque arrow is still drawn 8 s later');
  if (!(expiry.lastWith <= k + torqueTicks && expiry.firstWithout > k + torqueTicks))
    throw new Error(`torque arrow expired at tick ${expiry.firstWithout} (last drawn with ${expiry.lastWith}), want just after ${k + torqueTicks}`);

  // Hover shows a body's axes; the list finds a body by name; selecting it shows its state, and
  // "follow" moves the camera's target to it; trails are drawn for a bounded number of bodies.
  const can = await rv('window.rigidView.screenOf("can")');
  await page.mouse.move(can.x, can.y);
  await until('the can\'s axes under the pointer', () => rv('window.rigidView.hovered() === "can"'), 3000);
  await page.fill('#search', 'eg');
  const rows = await page.$$eval('#bodylist .row', (r) => r.map((x) => x.textContent));
  if (rows.length !== 1 || !rows[0].endsWith('egg')) throw new Error(`search 'eg' lists ${JSON.stringify(rows)}`);
  await page.click('#bodylist .row');
  const egg = await rv('window.rigidView.bodyState("egg")');
  const shownP = (await page.textContent('#selp')).split(',').map(Number);
  if (!(await page.textContent('#selname')).startsWith('egg') ||
      Math.max(...shownP.map((x, i) => Math.abs(x - egg.position[i]))) > 1e-3)
    throw new Error(`selected: ${await page.textContent('#selected')} (egg at ${egg.position})`);
  await page.check('#follow');
  await until('the camera to follow the egg', () => rv(`(() => { const t = window.rigidView.target(), p = window.rigidView.bodyState("egg").position; return Math.hypot(t[0] - p[0], t[1] - p[1], t[2] - p[2]) < 1e-6; })()`), 3000);
  await page.uncheck('#follow');
  const pill = await rv('window.rigidView.screenOf("pill")');  // a click on a body selects it
  await page.mouse.click(pill.x, pill.y);
  await until('the pill selected by a click', () => rv('window.rigidView.selected === "pill"'), 3000);
  await page.check('#trails');
  await until('trails', () => rv('window.rigidView.trails > 0 && window.rigidView.trails <= 16'), 3000);

  // The plots: drift samples (the selected body's, else the largest) and lateness per Stats.
  // Selecting the pill above cleared the drift chart (received counts since the page opened), so
  // wait for it to hold a sample again.
  const plots = await until('the plots to receive data',
                            () => rv('(() => { const p = window.rigidView.plots(); return p.drift > 10 && p.lateness > 0 && p.lastDrift && p.lastLateness ? p : null; })()'), 5000);
  if (!plots.lastDrift.every(Number.isFinite) || !(plots.lastLateness[0] >= 0)) throw new Error(`plots: ${JSON.stringify(plots)}`);

  // Garbage from a page: refused with a reason, counted.
  const refusal = await page.evaluate(() => new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.onopen = () => ws.send('{"op":"launch","id":1}');
    ws.binaryType = 'arraybuffer';
    ws.onmessage = (e) => { if (typeof e.data !== 'string') return; const m = JSON.parse(e.data); if (m.type === 'error') { ws.close(); resolve(m.message); } };
    setTimeout(() => resolve('no answer'), 5000);
  }));
  if (refusal !== 'unknown op launch') throw new Error(`garbage answered: ${refusal}`);

  // Flow control: a page that does not acknowledge the states it drew gets at most four
  // (kMaxUnackedStates, server.hpp); each {"op":"ack"} lets one more through (a slow page's states
  // wait in rigid-view, newest only).
  const flow = await page.evaluate(() => new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.binaryType = 'arraybuffer';
    let states = 0;
    const counts = [];
    ws.onmessage = (e) => { if (typeof e.data !== 'string') states += 1; };
    setTimeout(() => { counts.push(states); ws.send('{"op":"ack"}'); }, 1000);
    setTimeout(() => { counts.push(states); ws.close(); resolve(counts); }, 2000);
  }));
  if (flow[0] !== 4 || flow[1] !== 5) throw new Error(`states to a page that acknowledges none, then one: ${flow}`);

  // The page applies only the newest of the states that came since its last frame and acknowledges
  // all of them. Its main thread kept busy for 0.3 s at a time, states queue up (up to four in
  // flight); the next frames skip some, until more have been skipped than may be in flight; states
  // keep coming afterwards, which they would not if the skipped ones were never acknowledged.
  const counters = 'window.rigidView.statesReceived, window.rigidView.frames';
  const skipped0 = await rv('window.rigidView.statesSkipped');
  let skipped = 0;
  for (let k = 0; k < 12 && skipped <= 4; ++k) {
    await rv('(() => { const end = performance.now() + 300; while (performance.now() < end); })()');
    await sleep(200);
    skipped = (await rv('window.rigidView.statesSkipped')) - skipped0;
  }
  if (skipped <= 4) throw new Error(`states replaced by newer ones before a frame applied them: ${skipped}, expected more than 4`);
  const [received0, frames0] = await rv(`[${counters}]`);
  await until('states after the skipped ones', async () => {
    const [received, frames] = await rv(`[${counters}]`);
    return received >= received0 + 20 && frames >= frames0 + 20;
  }, 10000);

  await manyBodies();

  await sleep(1500);  // a Stats report in the HUD
  const hud = await page.textContent('#hud');
  if (!/rtf/.test(hud) || (await page.textContent('#overruns')) === '–') throw new Error(`HUD: ${hud}`);
  await page.screenshot({ path: join(outDir, 'rigid-view.png') });
  if (consoleErrors.length) throw new Error(`console errors: ${consoleErrors.join(' | ')}`);

  await harness.browser.close();
  harness.browser = null;
  view.kill('SIGTERM');
  const viewCode = await Promise.race([view.done, sleep(5000).then(() => 'timeout')]);
  if (viewCode !== 0) throw new Error(`rigid-view exited with ${viewCode}`);
  if (!/refused: frames [1-9]/.test(view.err)) throw new Error(`rigid-view did not count the refusal: ${view.err}`);
  server.kill('SIGTERM');
  await Promise.race([server.done, sleep(5000)]);
  clearTimeout(harness.deadline);
  await harness.cleanup();
  console.log('PASS');
} catch (e) {
  fail(e.message);
}

// rigid-view FILE in a real browser: rigidd on a small scene (unique --prefix) recorded for 3 s by
// rigid-record, then `rigid-view FILE` and the page in Debian's headless Chromium
// (playwright-core, never a downloaded browser). Checks: the page is in playback mode with its
// timeline and without rigidd's controls; play advances the tick, pause holds it; a seek with the
// slider and a seek by tick each draw the recorded pose of the spinning body at that state, equal
// to the one `rigid-record export --csv` (an independent reader of the file) prints, and the HUD
// the recorded Stats; speed is answered; a live command and a bad value are refused and counted;
// no console errors; a file that is not a recording is one line and exit status 1. rigidd also
// journals the run (--journal): `rigid-view JOURNAL` replays it, and a seek in it draws the same
// recorded poses bit for bit (the journal's states are the ones rigidd published). A push (rigidctl
// push, 0.2 s) during the recording: seeking to states around it, its arrow is drawn exactly with
// the states its ticks produced (k < tick <= k + 40), in the recording and in the journal.
// Screenshot: OUTDIR/rigid-view-playback.png.
// usage: node playback_test.mjs RIGIDD RIGID_RECORD RIGID_VIEW SCENE OUTDIR RIGIDCTL
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromium } from 'playwright-core';

import { browserHarness, Processes, sleep, until as untilOr } from './processes.mjs';

const [rigidd, rigidRecord, rigidView, sceneFile, outDir, rigidctl] = process.argv.slice(2);
const prefix = `viewplay${process.pid}`;
const bus = ['--transport', 'dds', '--prefix', prefix];
const work = mkdtempSync(join(tmpdir(), 'rigid-view-playback-'));
const processes = new Processes();
const start = (exe, args) => processes.start(exe, args);
const harness = browserHarness(processes, work, 80);
const { consoleErrors, fail } = harness;
const exited = (child, ms) => Processes.exited(child, ms);
const until = (what, check, ms = 10000) => untilOr(what, check, ms);

try {
  // A 3 s recording of rigidd (200 Hz, every tick published), and its states as CSV; rigidd's
  // journal of the same run.
  const recording = join(work, 'run.rlog');
  const journal = join(work, 'run.journal');
  const server = start(rigidd, ['--scene', sceneFile, '--journal', journal, ...bus]);
  const recorder = start(rigidRecord, ['record', recording, '--duration', '3', ...bus]);
  // A push on the ball a second in: 0.2 s at 200 Hz, 40 ticks from the tick it was accepted at.
  await sleep(1000);
  const pusher = start(rigidctl, ['push', 'ball', '--force', '5,0,0', '--for', '0.2', '--timeout', '10', ...bus]);
  if (await exited(pusher, 12000) !== 0) throw new Error(`rigidctl push: ${pusher.err}`);
  const pushTick = Number((pusher.out.match(/accepted at tick (\d+)/) || [])[1]);
  if (!Number.isInteger(pushTick)) throw new Error(`rigidctl push printed '${pusher.out}'`);
  const pushTicks = 40;
  const recorded = await exited(recorder, 20000);
  if (recorded !== 0) throw new Error(`rigid-record record: ${recorded}: ${recorder.err}`);
  process.kill(server.pid, 'SIGTERM');
  await exited(server, 5000);
  const csvFile = join(work, 'run.csv');
  const exporter = start(rigidRecord, ['export', recording, '--csv', csvFile]);
  if (await exited(exporter, 20000) !== 0) throw new Error(`rigid-record export: ${exporter.err}`);
  // t -> the spinner's row: position, orientation (w, x, y, z), as printed (%.17g: exact).
  const spinnerAt = new Map();
  for (const line of readFileSync(csvFile, 'utf8').split('\n').slice(1)) {
    const f = line.split(',');
    if (f[1] === 'spinner') spinnerAt.set(Number(f[0]), { position: f.slice(2, 5).map(Number), orientation: f.slice(5, 9).map(Number) });
  }
  const times = [...spinnerAt.keys()];
  if (times.length < 200) throw new Error(`only ${times.length} states recorded in 3 s`);
  console.log(`recorded ${times.length} states, t = ${times[0]} to ${times[times.length - 1]} s`);

  // A file that is not a recording: one line naming it, exit status 1.
  const bad = join(work, 'bad.rlog');
  writeFileSync(bad, 'RIGIDLOG\x01\x00\x00\x00garbage');
  const refused = start(rigidView, ['--listen', '127.0.0.1:0', bad]);
  const refusedCode = await exited(refused, 10000);
  const lines = refused.err.trim().split('\n');
  if (refusedCode !== 1 || lines.length !== 1 || !lines[0].startsWith(`rigid-view: ${bad}: `)) {
    throw new Error(`a bad file: exit ${refusedCode}, stderr '${refused.err}'`);
  }

  const view = start(rigidView, ['--listen', '127.0.0.1:0', recording]);
  const url = await until('rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  console.log(`rigid-view at ${url}: ${view.out.trim()}`);

  harness.browser = await chromium.launchPersistentContext(join(work, 'profile'), {
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

  // Playback mode: the timeline, not rigidd's controls; paused on the first state.
  await until('the scene and the first state',
              () => rv('window.rigidView.mode === "playback" && window.rigidView.bodies.length === 6 && window.rigidView.frames >= 1 && window.rigidView.playback !== null'), 20000)
    .catch(async (e) => { throw new Error(`${e.message}: ${await rv('JSON.stringify({mode: window.rigidView.mode, bodies: window.rigidView.bodies.length, frames: window.rigidView.frames})').catch((x) => String(x))}`); });
  if (!(await page.isVisible('#timeline')) || await page.isVisible('#controls')) throw new Error('the timeline is not shown instead of the controls');
  const first = await rv('window.rigidView.playback');
  if (first.playing || first.index !== 0 || first.states !== times.length) throw new Error(`at start: ${JSON.stringify(first)}`);
  if (first.start !== times[0] || first.end !== times[times.length - 1]) throw new Error(`timeline [${first.start}, ${first.end}], recording [${times[0]}, ${times[times.length - 1]}]`);

  async function answered(op, act) {
    const before = await rv('window.rigidView.replies.length');
    await act();
    const reply = await until(`the answer to ${op}`, () => rv(`window.rigidView.replies.slice(${before}).find((r) => r.op === "${op}")`));
    if (!reply.ok) throw new Error(`${op} answered ${JSON.stringify(reply)}`);
    return reply;
  }
  const tick = () => rv('window.rigidView.lastState.tick');

  // Play: the tick advances.
  const t0 = await tick();
  await answered('play', () => page.click('#tl-play'));
  await until('the tick to advance by 40 (0.2 s)', async () => (await tick()) >= t0 + 40, 5000);
  if ((await page.textContent('#tl-play')) !== 'pause') throw new Error('the button does not offer pause while playing');
  // Pause: it holds.
  const paused = await answered('pause', () => page.click('#tl-play'));
  await until('the paused state drawn', async () => (await tick()) === paused.tick, 3000);
  await sleep(600);
  if ((await tick()) !== paused.tick) throw new Error(`paused at tick ${paused.tick}, the page moved on to ${await tick()}`);

  // The drawn pose of the spinner equals the recorded one at the page's state, bit for bit.
  async function drawnMatchesRecording(what, on = page) {
    const state = await on.evaluate('window.rigidView.lastState');
    const recorded = spinnerAt.get(state.simTime);
    if (!recorded) throw new Error(`${what}: the page shows t=${state.simTime}, not a recorded time`);
    const drawn = await on.evaluate('window.rigidView.renderedPose("spinner")');
    if (JSON.stringify(drawn.position) !== JSON.stringify(recorded.position) ||
        JSON.stringify(drawn.orientation) !== JSON.stringify(recorded.orientation)) {
      throw new Error(`${what}: drawn ${JSON.stringify(drawn)}, recorded ${JSON.stringify(recorded)}`);
    }
    return state;
  }
  await drawnMatchesRecording('paused');

  // Seek with the slider to a recorded time, a third of the way.
  const target = times[Math.floor(times.length / 3)];
  const sought = await answered('seek', () => page.locator('#tl-slider').fill(String(target)));
  await until(`the state at t=${target}`, () => rv(`window.rigidView.lastState.simTime === ${target}`), 5000);
  const atSlider = await drawnMatchesRecording('slider seek');
  if (atSlider.tick !== sought.tick) throw new Error(`seek answered tick ${sought.tick}, page shows ${atSlider.tick}`);

  // Seek by tick (two thirds of the way): the page shows that tick, the recording's pose there.
  const dt = await rv('window.rigidView.scene.dt');
  const wanted = Math.round(times[Math.floor((2 * times.length) / 3)] / dt);
  const byTick = await answered('seek', () => rv(`window.rigidView.control("seek", { tick: ${wanted} })`));
  if (byTick.tick !== wanted) throw new Error(`seek to tick ${wanted} answered tick ${byTick.tick}`);
  await until(`the state at tick ${wanted}`, async () => (await tick()) === wanted, 5000);
  const atTick = await drawnMatchesRecording('seek by tick');
  if (Math.abs(atTick.simTime - wanted * dt) > 1e-9) throw new Error(`tick ${wanted} shown at t=${atTick.simTime}`);
  if (!(await page.textContent('#tl-time')).includes(`tick ${wanted}`)) throw new Error(`the timeline shows '${await page.textContent('#tl-time')}'`);

  // The push's arrow: seek to states around it; drawn exactly with the states its ticks produced.
  const ballId = (await rv('window.rigidView.bodies')).find((b) => b.name === 'ball').id;
  async function pushArrowAround(on, what) {
    const ask = (expr) => on.evaluate(expr);
    for (const at of [pushTick, pushTick + 1, pushTick + 20, pushTick + pushTicks, pushTick + pushTicks + 1, pushTick + 80]) {
      const before = await ask('window.rigidView.replies.length');
      await ask(`window.rigidView.control("seek", { tick: ${at} })`);
      const reply = await until(`the answer to seek ${at}`, () => ask(`window.rigidView.replies.slice(${before}).find((r) => r.op === "seek")`));
      // The state shown (the nearest if that tick was not recorded), and the arrows drawn with it
      // (read in an animation frame after the page's own).
      await until(`${what}: the state at tick ${reply.tick}`, () => ask(`window.rigidView.lastState.tick === ${reply.tick}`), 5000);
      await sleep(100);  // the wrenches message and the state: a frame or two
      const drawn = await on.evaluate((id) => new Promise((resolve) => requestAnimationFrame(() => {
        const v = window.rigidView;
        resolve({ tick: v.lastState.tick, arrow: v.arrows.find((a) => a.body === id) || null });
      })), ballId);
      const want = drawn.tick > pushTick && drawn.tick <= pushTick + pushTicks;
      if (!!drawn.arrow !== want) throw new Error(`${what}: push accepted at tick ${pushTick}: at tick ${drawn.tick} the arrow is ${drawn.arrow ? '' : 'not '}drawn`);
      if (want && !(drawn.arrow.force[0] === 5 && drawn.arrow.force[1] === 0)) throw new Error(`${what}: the push's arrow ${JSON.stringify(drawn.arrow)}`);
    }
  }
  await pushArrowAround(page, 'recording');

  // The HUD shows rigidd's Stats as recorded before that state (rigidd sends them once a second).
  await until('the recorded Stats in the HUD', async () => (await page.textContent('#overruns')) !== '–', 3000);

  // Speed from the selector: answered, the timeline says so.
  await answered('speed', () => page.selectOption('#tl-speed', '4'));
  await until('speed 4 in the timeline', () => rv('window.rigidView.playback.speed === 4'), 3000);

  // A live command, and a bad value: refused with their reasons.
  const refusals = await page.evaluate(() => new Promise((resolve) => {
    const got = {};
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.binaryType = 'arraybuffer';
    ws.onopen = () => {
      ws.send('{"op":"step","id":77,"steps":1}');
      ws.send('{"op":"speed","id":78,"speed":1000}');
    };
    ws.onmessage = (e) => {
      if (typeof e.data !== 'string') return;
      const m = JSON.parse(e.data);
      if (m.type === 'reply' && m.id === 77) got.step = m;
      if (m.type === 'error') got.error = m.message;
      if (got.step && got.error) { ws.close(); resolve(got); }
    };
    setTimeout(() => resolve(got), 5000);
  }));
  if (!refusals.step || refusals.step.ok || !/not while playing a recording/.test(refusals.step.message)) throw new Error(`step in playback answered ${JSON.stringify(refusals.step)}`);
  if (refusals.error !== 'speed: expected a number in [1/64, 64]') throw new Error(`speed 1000 answered ${refusals.error}`);

  await page.screenshot({ path: join(outDir, 'rigid-view-playback.png') });

  // The journal, in a second rigid-view and page: replayed from tick 0 (rigidd journals from its
  // start, rigid-record joined later), every state verified against rigidd's hashes; at the
  // recording's times it draws the recorded poses.
  const journalView = start(rigidView, ['--listen', '127.0.0.1:0', journal]);
  const journalUrl = await until('rigid-view JOURNAL to print its URL',
                                 () => (journalView.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  console.log(`rigid-view at ${journalUrl}: ${journalView.out.trim()}`);
  if (!journalView.out.includes('rigidd journal, replayed')) throw new Error(`rigid-view JOURNAL: ${journalView.out}`);
  const jpage = await harness.browser.newPage();
  harness.watch(jpage);
  await jpage.goto(journalUrl);
  await until('the journal\'s scene and first state',
              () => jpage.evaluate('window.rigidView.mode === "playback" && window.rigidView.bodies.length === 6 && window.rigidView.playback !== null && window.rigidView.frames >= 1'), 20000);
  const jfirst = await jpage.evaluate('window.rigidView.playback');
  if (jfirst.start !== 0 || jfirst.end < times[times.length - 1] || jfirst.states < times.length) {
    throw new Error(`the journal's timeline: ${JSON.stringify(jfirst)}, the recording's [${times[0]}, ${times[times.length - 1]}], ${times.length} states`);
  }
  for (const at of [times[0], target, times[times.length - 1]]) {
    await jpage.locator('#tl-slider').fill(String(at));
    await until(`the journal's state at t=${at}`, () => jpage.evaluate(`window.rigidView.lastState.simTime === ${at}`), 5000);
    await drawnMatchesRecording(`the journal at t=${at}`, jpage);
  }
  await pushArrowAround(jpage, 'journal');
  if (consoleErrors.length) throw new Error(`console errors: ${consoleErrors.join(' | ')}`);
  process.kill(journalView.pid, 'SIGTERM');
  if (await exited(journalView, 5000) !== 0) throw new Error(`rigid-view JOURNAL exited with ${journalView.exitCode}: ${journalView.err}`);

  await harness.browser.close();
  harness.browser = null;
  process.kill(view.pid, 'SIGTERM');
  const viewCode = await exited(view, 5000);
  if (viewCode !== 0) throw new Error(`rigid-view exited with ${viewCode}`);
  if (!/refused: frames [1-9]\d*, commands [1-9]/.test(view.err)) throw new Error(`rigid-view did not count the refusals: ${view.err}`);
  clearTimeout(harness.deadline);
  await harness.cleanup();
  console.log('PASS');
} catch (e) {
  fail(e.message);
}

// rigid-view in a real browser: rigidd on a small scene (unique --prefix), rigid-view on a free
// port, the page in Debian's headless Chromium (playwright-core, never a downloaded browser).
// Checks: no console errors; the scene's bodies drawn; the pose drawn for a spinning body equals
// the state rigidd published (read independently with rigidctl echo --csv); pause, step, reset and
// resume answered by rigidd; garbage from a page refused. Screenshot: OUTDIR/rigid-view.png.
// usage: node browser_test.mjs RIGIDD RIGID_VIEW RIGIDCTL SCENE OUTDIR
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const [rigidd, rigidView, rigidctl, sceneFile, outDir] = process.argv.slice(2);
const prefix = `viewtest${process.pid}`;
// ctest sets CYCLONEDDS_URI; by hand, the source tree's loopback config (two levels up).
const loopbackConfig = fileURLToPath(new URL('../../config/cyclonedds.xml', import.meta.url));
const env = { ...process.env, CYCLONEDDS_URI: process.env.CYCLONEDDS_URI || `file://${loopbackConfig}` };
const bus = ['--transport', 'dds', '--prefix', prefix];
const children = [];
let browser = null;
const consoleErrors = [];
const profile = mkdtempSync(join(tmpdir(), 'rigid-view-chromium-'));

function start(exe, args) {
  const child = spawn(exe, args, { env, stdio: ['ignore', 'pipe', 'pipe'] });
  child.out = '';
  child.err = '';
  child.stdout.on('data', (d) => { child.out += d; });
  child.stderr.on('data', (d) => { child.err += d; });
  child.done = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
  children.push(child);
  return child;
}
async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
  rmSync(profile, { recursive: true, force: true });
}
function fail(message) {
  console.error(`FAIL: ${message}`);
  if (consoleErrors.length) console.error(`console errors: ${consoleErrors.join(' | ')}`);
  for (const c of children) console.error(`--- ${c.spawnargs[0]} stderr:\n${c.err}`);
  cleanup().finally(() => process.exit(1));
}
const deadline = setTimeout(() => fail('took more than 120 s'), 120000);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
async function until(what, check, ms = 15000) {
  const end = Date.now() + ms;
  for (;;) {
    const v = await check();
    if (v) return v;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await sleep(50);
  }
}

try {
  const server = start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = start(rigidView, [...bus, '--listen', '127.0.0.1:0']);
  const url = await until('rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0]);
  console.log(`rigid-view at ${url}`);

  browser = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium', headless: true, chromiumSandbox: false,
    viewport: { width: 1000, height: 700 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = browser.pages()[0] || await browser.newPage();
  page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
  await page.goto(url);

  const rv = (expr) => page.evaluate(expr);
  // The scene's bodies, each with its shape, and states arriving.
  await until('the scene and states', () => rv('window.rigidView.bodies.length === 6 && window.rigidView.frames > 5'), 40000)
    .catch(async (e) => { throw new Error(`${e.message}: page has ${await rv('JSON.stringify({connected: window.rigidView.connected, bodies: window.rigidView.bodies.length, frames: window.rigidView.frames})').catch((x) => String(x))}`); });
  const shapes = await rv('Object.fromEntries(window.rigidView.bodies.map((b) => [b.name, b.shape + (b.fromMoments ? "*" : "")]))');
  const want = { spinner: 'box', ball: 'sphere', can: 'cylinder', pill: 'capsule', egg: 'ellipsoid', lump: 'box*' };
  if (JSON.stringify(shapes) !== JSON.stringify(want)) throw new Error(`bodies drawn: ${JSON.stringify(shapes)}`);
  // The frame rate is bounded (~60 Hz) although rigidd publishes at 200 Hz.
  const f0 = await rv('window.rigidView.frames');
  await sleep(1000);
  const rate = (await rv('window.rigidView.frames')) - f0;
  if (rate < 20 || rate > 75) throw new Error(`${rate} frames in 1 s (expected about 60)`);
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
  const code = await Promise.race([echo.done, sleep(25000).then(() => 'timeout')]);
  if (code !== 0) throw new Error(`rigidctl echo: ${code}: ${echo.err}`);
  const row = echo.out.split('\n').find((l) => l.split(',')[1] === 'spinner');
  if (!row) throw new Error(`no spinner row in rigidctl's output: ${echo.out}`);
  const v = row.split(',').map(Number);
  const t = v[0], published = { position: v.slice(2, 5), orientation: v.slice(5, 9) };
  await until(`the page to draw the state at t=${t}`,
              () => rv(`Math.abs(window.rigidView.lastState.simTime - ${t}) < 1e-9`), 5000);
  const drawn = await rv('window.rigidView.renderedPose("spinner")');
  const err = Math.max(...published.position.map((x, i) => Math.abs(x - drawn.position[i])),
                       ...published.orientation.map((x, i) => Math.abs(x - drawn.orientation[i])));
  console.log(`spinner at t=${t}: published ${JSON.stringify(published)}, drawn ${JSON.stringify(drawn)}`);
  if (!(err < 1e-9)) throw new Error(`drawn pose differs from the published state by ${err}`);
  if (Math.abs(published.orientation[0]) > 0.999) throw new Error('the spinner has not turned');

  const stepReply = await press('step', 'step');
  await until('the page to draw the stepped state',
              () => rv(`window.rigidView.lastState.tick === ${stepReply.tick}`), 5000);
  const reset = await press('reset', 'reset');
  if (reset.tick !== 0) throw new Error(`reset answered at tick ${reset.tick}`);
  await press('resume', 'resume');

  // Garbage from a page: refused with a reason, counted.
  const refusal = await page.evaluate(() => new Promise((resolve) => {
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.onopen = () => ws.send('{"op":"launch","id":1}');
    ws.binaryType = 'arraybuffer';
    ws.onmessage = (e) => { if (typeof e.data !== 'string') return; const m = JSON.parse(e.data); if (m.type === 'error') { ws.close(); resolve(m.message); } };
    setTimeout(() => resolve('no answer'), 5000);
  }));
  if (refusal !== 'unknown op launch') throw new Error(`garbage answered: ${refusal}`);

  await sleep(1500);  // a Stats report in the HUD
  const hud = await page.textContent('#hud');
  if (!/rtf/.test(hud) || (await page.textContent('#overruns')) === '–') throw new Error(`HUD: ${hud}`);
  await page.screenshot({ path: join(outDir, 'rigid-view.png') });
  if (consoleErrors.length) throw new Error(`console errors: ${consoleErrors.join(' | ')}`);

  await browser.close();
  browser = null;
  view.kill('SIGTERM');
  const viewCode = await Promise.race([view.done, sleep(5000).then(() => 'timeout')]);
  if (viewCode !== 0) throw new Error(`rigid-view exited with ${viewCode}`);
  if (!/refused: frames [1-9]/.test(view.err)) throw new Error(`rigid-view did not count the refusal: ${view.err}`);
  server.kill('SIGTERM');
  await Promise.race([server.done, sleep(5000)]);
  clearTimeout(deadline);
  await cleanup();
  console.log('PASS');
} catch (e) {
  fail(e.message);
}

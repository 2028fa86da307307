// rigid-view in headless Chromium: frames per second drawn for scenes of 10^3 and 10^4 bodies, and
// the latency from rigidd's publish (the state's stamp_ns, CLOCK_REALTIME) to the page's rendered
// frame that draws it (p50, p99). A benchmark, not a test: it asserts nothing (README in this
// directory says how to run it and what the targets are).
//
// For each size it writes a scene (a cubic lattice of spheres and boxes in zero gravity, each
// spinning), starts rigidd on it (own --prefix, DDS on loopback) and rigid-view on a free port, loads
// the page in Debian's /usr/bin/chromium (software WebGL: SwiftShader, as the browser test), waits
// for every body to be drawn, then counts rendered frames and state frames for --seconds.
// --web-dirs A,B serves each size with each page in turn (rigid-view --web-dir: an old page against
// a new one, side by side), --repeat N runs every pair N times and prints the medians.
//
// usage: node view_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000,10000] [--seconds 10] [--rate 100]
//                           [--web-dirs DIR,...] [--repeat N] [--csv FILE]
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync, appendFileSync, existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';

// The browser test's pinned playwright-core (npm ci --prefix tests/view): one lockfile for both.
const require = createRequire(fileURLToPath(new URL('../../tests/view/package.json', import.meta.url)));
const { chromium } = require('playwright-core');

function usage(message) {
  console.error(`view_bench: ${message}\nusage: node view_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000,10000] [--seconds 10] [--rate 100] [--web-dirs DIR,...] [--repeat N] [--csv FILE]`);
  process.exit(2);
}
const argv = process.argv.slice(2);
if (argv.length < 2) usage('needs the paths of rigidd and rigid-view');
const [rigidd, rigidView] = argv;
for (const exe of [rigidd, rigidView]) if (!existsSync(exe)) usage(`no such executable: ${exe}`);
const opt = { bodies: [1000, 10000], seconds: 10, rate: 100, csv: null, webDirs: [null], repeat: 1 };
for (let i = 2; i < argv.length; i += 2) {
  const key = argv[i], value = argv[i + 1];
  if (value === undefined) usage(`${key}: missing value`);
  if (key === '--bodies') {
    opt.bodies = value.split(',').map(Number);
    if (!opt.bodies.every((n) => Number.isInteger(n) && n >= 1 && n <= 100000)) usage(`--bodies: expected integers in [1, 100000], got ${value}`);
  } else if (key === '--seconds') {
    opt.seconds = Number(value);
    if (!(opt.seconds >= 1 && opt.seconds <= 600)) usage(`--seconds: expected a number in [1, 600], got ${value}`);
  } else if (key === '--rate') {
    opt.rate = Number(value);
    if (!(Number.isInteger(opt.rate) && opt.rate >= 1 && opt.rate <= 1000)) usage(`--rate: expected an integer in [1, 1000], got ${value}`);
  } else if (key === '--web-dirs') {
    opt.webDirs = value.split(',');
    for (const d of opt.webDirs) if (!existsSync(join(d, 'app.js'))) usage(`--web-dirs: no app.js in ${d}`);
  } else if (key === '--repeat') {
    opt.repeat = Number(value);
    if (!(Number.isInteger(opt.repeat) && opt.repeat >= 1 && opt.repeat <= 20)) usage(`--repeat: expected an integer in [1, 20], got ${value}`);
  } else if (key === '--csv') {
    opt.csv = value;
  } else {
    usage(`unknown option ${key}`);
  }
}

const loopbackConfig = fileURLToPath(new URL('../../config/cyclonedds.xml', import.meta.url));
const env = { ...process.env, CYCLONEDDS_URI: process.env.CYCLONEDDS_URI || `file://${loopbackConfig}` };
const work = mkdtempSync(join(tmpdir(), 'rigid-view-bench-'));
const children = [];
let browser = null;
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

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
async function stop(child) {
  if (child.exitCode === null) child.kill('SIGTERM');
  await Promise.race([child.done, sleep(5000)]);
}
async function until(what, check, ms) {
  const end = Date.now() + ms;
  for (;;) {
    const v = await check();
    if (v) return v;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await sleep(100);
  }
}
async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
  rmSync(work, { recursive: true, force: true });
}
const watchdog = setTimeout(() => {
  console.error('view_bench: took more than 10 minutes; stopping');
  cleanup().finally(() => process.exit(1));
}, 600000);

// n bodies on a cubic lattice 0.3 m apart around the origin, alternately spheres and boxes (two
// meshes), each spinning about a different axis; zero gravity keeps them in view.
function sceneText(n) {
  const side = Math.ceil(Math.cbrt(n));
  const lines = [`# view_bench: ${n} bodies`,
                 `world { rate_hz: ${opt.rate}  publish_every: 1  gravity { } }`];
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

async function run(n, webDir) {
  const sceneFile = join(work, `bench_${n}.pbtxt`);
  writeFileSync(sceneFile, sceneText(n));
  const bus = ['--transport', 'dds', '--prefix', `viewbench${process.pid}n${n}`];
  const server = start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = start(rigidView, [...bus, '--listen', '127.0.0.1:0', ...(webDir ? ['--web-dir', webDir] : [])]);
  const url = await until('rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0], 30000);
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  const rv = (expr) => page.evaluate(expr);
  await until(`${n} bodies drawn`, () => rv(`window.rigidView.bodies.length === ${n} && window.rigidView.frames >= 2`), 120000);
  await sleep(2000);  // warm-up: shaders compiled, the page's allocations settled
  await rv('window.rigidView.clearLatencies()');
  const r0 = await rv('[window.rigidView.rendered, window.rigidView.frames, performance.now(), window.rigidView.renderMs, window.rigidView.stateMs]');
  await sleep(opt.seconds * 1000);
  const r1 = await rv('[window.rigidView.rendered, window.rigidView.frames, performance.now(), window.rigidView.renderMs, window.rigidView.stateMs]');
  const latencies = (await rv('window.rigidView.latencies()')).sort((a, b) => a - b);
  // Where the latency goes (pages that split it): publish -> worker -> main thread -> frame.
  const parts = await rv('window.rigidView.latencyParts ? window.rigidView.latencyParts() : null');
  const instances = await rv('window.rigidView.instances()');
  await page.close();
  await stop(view);
  await stop(server);
  if (errors.length) throw new Error(`page errors: ${errors.join(' | ')}`);
  const seconds = (r1[2] - r0[2]) / 1000;
  return { bodies: n, page: webDir || '(default)', path: instances.path || 'instanced',
           meshes: instances.meshes, fps: (r1[0] - r0[0]) / seconds,
           states_per_s: (r1[1] - r0[1]) / seconds, latency_p50_ms: quantile(latencies, 0.5),
           latency_p99_ms: quantile(latencies, 0.99), latency_samples: latencies.length, seconds,
           render_ms: (r1[3] - r0[3]) / Math.max(r1[0] - r0[0], 1),
           state_ms: (r1[4] - r0[4]) / Math.max(r1[1] - r0[1], 1),
           to_worker_p50_ms: parts ? median(parts.toWorker) : NaN,
           to_main_p50_ms: parts ? median(parts.toMain) : NaN,
           to_frame_p50_ms: parts ? median(parts.toFrame) : NaN };
}

try {
  browser = await chromium.launch({
    executablePath: '/usr/bin/chromium', headless: true, chromiumSandbox: false,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const results = [];
  // Interleaved (size, page) pairs: every page meets the same machine load, run after run.
  for (let k = 0; k < opt.repeat; ++k) {
    for (const n of opt.bodies) {
      for (const webDir of opt.webDirs) {
        const r = await run(n, webDir);
        results.push(r);
        console.log(`${n} bodies, page ${r.page} (${r.meshes} ${r.path} meshes): ${r.fps.toFixed(1)} frames/s, ` +
                    `${r.states_per_s.toFixed(1)} states/s drawn, latency publish -> frame ` +
                    `p50 ${r.latency_p50_ms.toFixed(1)} ms, p99 ${r.latency_p99_ms.toFixed(1)} ms ` +
                    `(${r.latency_samples} states, ${r.seconds.toFixed(1)} s; p50 to the worker ` +
                    `${r.to_worker_p50_ms.toFixed(1)}, to the main thread ${r.to_main_p50_ms.toFixed(1)}, ` +
                    `to the frame ${r.to_frame_p50_ms.toFixed(1)} ms); per frame: render ` +
                    `${r.render_ms.toFixed(2)} ms, per state: apply ${r.state_ms.toFixed(2)} ms`);
      }
    }
  }
  if (opt.repeat > 1) {
    console.log(`medians of ${opt.repeat} runs:`);
    for (const n of opt.bodies) {
      for (const webDir of opt.webDirs) {
        const rs = results.filter((r) => r.bodies === n && r.page === (webDir || '(default)'));
        const m = (key) => median(rs.map((r) => r[key])).toFixed(1);
        console.log(`  ${n} bodies, page ${rs[0].page}: ${m('fps')} frames/s, ${m('states_per_s')} states/s, ` +
                    `latency p50 ${m('latency_p50_ms')} ms, p99 ${m('latency_p99_ms')} ms ` +
                    `(to the worker ${m('to_worker_p50_ms')}, main thread ${m('to_main_p50_ms')}, frame ${m('to_frame_p50_ms')})`);
      }
    }
  }
  if (opt.csv) {
    const header = 'bodies,page,path,meshes,fps,states_per_s,latency_p50_ms,latency_p99_ms,latency_samples,seconds,render_ms,state_ms,to_worker_p50_ms,to_main_p50_ms,to_frame_p50_ms\n';
    if (!existsSync(opt.csv)) writeFileSync(opt.csv, header);
    for (const r of results)
      appendFileSync(opt.csv, `${r.bodies},${r.page},${r.path},${r.meshes},${r.fps},${r.states_per_s},${r.latency_p50_ms},${r.latency_p99_ms},${r.latency_samples},${r.seconds},${r.render_ms},${r.state_ms},${r.to_worker_p50_ms},${r.to_main_p50_ms},${r.to_frame_p50_ms}\n`);
  }
  clearTimeout(watchdog);
  await cleanup();
} catch (e) {
  console.error(`view_bench: ${e.message}`);
  for (const c of children) if (c.err) console.error(`--- ${c.spawnargs[0]} stderr:\n${c.err.slice(-2000)}`);
  await cleanup();
  process.exit(1);
}

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
// --driver cdp (the default) drives Chromium over its DevTools pipe with no Network domain
// (cdp_browser.mjs says why); --driver playwright as the browser test does (older figures in
// bench/notes/view-bench.md were taken so).
//
// --rigidd-cost: what rigid-view costs rigidd instead (issue 11: "no cost to rigidd"). One rigidd,
// realtime, --rate (default 1000) Hz on a scene of --bodies (default 1000) bodies publishing every
// --publish-every (default 10) ticks, runs throughout; windows of --seconds (default 20) cycle
// through three conditions, --repeat (default 3) times: no rigid-view; rigid-view with no page;
// rigid-view with two pages open (headless Chromium). rigidd's Stats (read by `rigidctl stats`,
// running throughout: the same listener in every condition) give per second its tick lateness
// p99 and its overruns; each window reports the median and the largest per-second p99 and the
// overruns it added, and each condition the medians over its windows.
// --browser-cpus LIST (either mode, cdp driver) runs Chromium under `taskset -c LIST`: e.g. 0 keeps
// it off CPU 1, the one rigidd pins its real-time threads to on a 2-CPU host (the last it may use).
// --paused pauses rigidd (from the page) before the window: what a page left open on a paused
// scene costs. With the cdp driver every run also reports the CPU time Chromium's processes took
// in the window (user + system, all of them: the page, the GPU process, the browser), in % of
// one CPU.
//
// usage: node view_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000,10000] [--seconds 10] [--rate 100]
//                           [--web-dirs DIR,...] [--repeat N] [--csv FILE] [--driver cdp|playwright]
//                           [--chromium-flags "--FLAG !--FLAG"] (added to / removed from the bench's own)
//                           [--paused]
//        node view_bench.mjs RIGIDD RIGID_VIEW --rigidd-cost [--rigidctl RIGIDCTL] [--bodies N]
//                           [--seconds S] [--rate HZ] [--publish-every K] [--repeat N]
//        either with [--browser-cpus LIST]
import { mkdtempSync, rmSync, writeFileSync, appendFileSync, existsSync, readdirSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { loadavg, tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

// The browser test's pinned playwright-core (npm ci --prefix tests/view): one lockfile for both.
const require = createRequire(fileURLToPath(new URL('../../tests/view/package.json', import.meta.url)));
const { chromium } = require('playwright-core');
const { Processes, sleep, until: untilEvery } = await import('../../tests/view/processes.mjs');
const { launchCdp } = await import('./cdp_browser.mjs');

function usage(message) {
  console.error(`view_bench: ${message}\nusage: node view_bench.mjs RIGIDD RIGID_VIEW [--bodies 1000,10000] [--seconds 10] [--rate 100] [--web-dirs DIR,...] [--repeat N] [--csv FILE] [--driver cdp|playwright] [--chromium-flags "FLAGS"] [--paused]\n       node view_bench.mjs RIGIDD RIGID_VIEW --rigidd-cost [--rigidctl RIGIDCTL] [--bodies N] [--seconds S] [--rate HZ] [--publish-every K] [--repeat N]\n       either with [--browser-cpus LIST] (--driver cdp)`);
  process.exit(2);
}
const argv = process.argv.slice(2);
if (argv.length < 2) usage('needs the paths of rigidd and rigid-view');
const [rigidd, rigidView] = argv;
for (const exe of [rigidd, rigidView]) if (!existsSync(exe)) usage(`no such executable: ${exe}`);
// --rigidd-cost (a flag: no value) changes the defaults: see the top.
const costMode = argv.includes('--rigidd-cost');
const flags = new Set(['--rigidd-cost', '--paused']);
const opt = costMode
  ? { bodies: [1000], seconds: 20, rate: 1000, csv: null, webDirs: [null], repeat: 3, publishEvery: 10,
      rigidctl: join(dirname(dirname(rigidView)), 'rigidctl'), driver: 'cdp' }
  : { bodies: [1000, 10000], seconds: 10, rate: 100, csv: null, webDirs: [null], repeat: 1, publishEvery: 1,
      driver: 'cdp' };
for (let i = 2; i < argv.length; i += 2) {
  const key = argv[i], value = argv[i + 1];
  if (flags.has(key)) {
    if (key === '--paused') opt.paused = true;
    --i;  // a flag
    continue;
  }
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
  } else if (key === '--publish-every') {
    opt.publishEvery = Number(value);
    if (!(Number.isInteger(opt.publishEvery) && opt.publishEvery >= 1 && opt.publishEvery <= 1000)) usage(`--publish-every: expected an integer in [1, 1000], got ${value}`);
  } else if (key === '--rigidctl') {
    opt.rigidctl = value;
  } else if (key === '--browser-cpus') {
    if (!/^\d+([-,]\d+)*$/.test(value)) usage(`--browser-cpus: expected a CPU list such as 0 or 0-2,4, got ${value}`);
    opt.browserCpus = value;
  } else if (key === '--chromium-flags') {
    // Space-separated, added after the bench's own (e.g. to compare compositing paths); !--FLAG
    // removes one of the bench's own.
    opt.chromiumFlags = value.split(' ').filter((f) => f.length);
    if (!opt.chromiumFlags.every((f) => /^!?--/.test(f))) usage(`--chromium-flags: expected flags starting with -- or !--, got ${value}`);
  } else if (key === '--driver') {
    if (value !== 'cdp' && value !== 'playwright') usage(`--driver: expected cdp or playwright, got ${value}`);
    opt.driver = value;
  } else {
    usage(`unknown option ${key}`);
  }
}

if (costMode) {
  if (opt.bodies.length !== 1) usage('--rigidd-cost: --bodies takes one size');
  if (opt.webDirs.length !== 1 || opt.csv || opt.paused) usage('--rigidd-cost: --web-dirs, --csv and --paused do not apply');
  if (!existsSync(opt.rigidctl)) usage(`--rigidctl: no such executable: ${opt.rigidctl}`);
  if (opt.seconds < 5) usage('--rigidd-cost: --seconds must be at least 5 (Stats come once a second)');
}

const work = mkdtempSync(join(tmpdir(), 'rigid-view-bench-'));
const processes = new Processes();
const start = (exe, args) => processes.start(exe, args);
const stop = (child) => processes.stop(child);
const until = (what, check, ms) => untilEvery(what, check, ms, 100);
let browser = null;
// A 1280x800 page, either driver's: goto, evaluate, on('pageerror'), close.
const newPage = () => (opt.driver === 'cdp' ? browser.newPage({ width: 1280, height: 800 })
                                             : browser.newPage({ viewport: { width: 1280, height: 800 } }));

async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  processes.stopAll();
  rmSync(work, { recursive: true, force: true });
}
// Ten minutes; --rigidd-cost: its windows plus a minute each to set up.
const watchdogS = costMode ? 3 * opt.repeat * (opt.seconds + 60) + 60 : 600;
const watchdog = setTimeout(() => {
  console.error(`view_bench: took more than ${watchdogS} s; stopping`);
  cleanup().finally(() => process.exit(1));
}, watchdogS * 1000);

// n bodies on a cubic lattice 0.3 m apart around the origin, alternately spheres and boxes (two
// meshes), each spinning about a different axis; zero gravity keeps them in view.
function sceneText(n) {
  const side = Math.ceil(Math.cbrt(n));
  const lines = [`# view_bench: ${n} bodies`,
                 `world { rate_hz: ${opt.rate}  publish_every: ${opt.publishEvery}  gravity { } }`];
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

// CPU time (s, user + system) of process `root` and all its descendants now living, from /proc
// (NaN without a pid: the playwright driver).
function treeCpuSeconds(root) {
  if (!root) return NaN;
  const stats = [];
  for (const entry of readdirSync('/proc')) {
    if (!/^\d+$/.test(entry)) continue;
    try {
      // Fields after the command's closing parenthesis: state ppid ... utime (14) stime (15).
      const text = readFileSync(`/proc/${entry}/stat`, 'utf8');
      const f = text.slice(text.lastIndexOf(')') + 2).split(' ');
      stats.push({ pid: Number(entry), ppid: Number(f[1]), ticks: Number(f[11]) + Number(f[12]) });
    } catch {
      // (gone meanwhile)
    }
  }
  const inTree = new Set([root]);
  for (let grew = true; grew;) {
    grew = false;
    for (const p of stats) if (!inTree.has(p.pid) && inTree.has(p.ppid)) { inTree.add(p.pid); grew = true; }
  }
  const kTicksPerSecond = 100;  // sysconf(_SC_CLK_TCK) on Linux
  return stats.filter((p) => inTree.has(p.pid)).reduce((sum, p) => sum + p.ticks, 0) / kTicksPerSecond;
}

async function run(n, webDir) {
  const sceneFile = join(work, `bench_${n}.pbtxt`);
  writeFileSync(sceneFile, sceneText(n));
  const bus = ['--transport', 'dds', '--prefix', `viewbench${process.pid}n${n}`];
  const server = start(rigidd, ['--scene', sceneFile, ...bus]);
  const view = start(rigidView, [...bus, '--listen', '127.0.0.1:0', ...(webDir ? ['--web-dir', webDir] : [])]);
  const url = await until('rigid-view to print its URL',
                          () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0], 30000);
  const page = await newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  const rv = (expr) => page.evaluate(expr);
  await until(`${n} bodies drawn`, () => rv(`window.rigidView.bodies.length === ${n} && window.rigidView.frames >= 2`), 120000);
  await sleep(2000);  // warm-up: shaders compiled, the page's allocations settled
  if (opt.paused) {
    await rv('window.rigidView.control("pause")');
    await until('rigidd paused', () => rv('window.rigidView.replies.some((r) => r.op === "pause" && r.ok)'), 10000);
    await sleep(1000);  // (past the page's linger after the last state that moved)
  }
  await rv('window.rigidView.clearLatencies()');
  const cpu0 = treeCpuSeconds(browser.pid);
  const r0 = await rv('[window.rigidView.rendered, window.rigidView.frames, performance.now(), window.rigidView.renderMs, window.rigidView.stateMs, window.rigidView.statesReceived ?? NaN, window.rigidView.statesSkipped ?? NaN]');
  await sleep(opt.seconds * 1000);
  const r1 = await rv('[window.rigidView.rendered, window.rigidView.frames, performance.now(), window.rigidView.renderMs, window.rigidView.stateMs, window.rigidView.statesReceived ?? NaN, window.rigidView.statesSkipped ?? NaN]');
  const cpu1 = treeCpuSeconds(browser.pid);
  const latencies = (await rv('window.rigidView.latencies()')).sort((a, b) => a - b);
  // Refreshes of the 60 Hz frame clock (headless Chromium's) the page missed in the window: an
  // interval between animation frames of k refreshes missed k - 1 (NaN for an older page that
  // keeps no frame timestamps).
  const times = await rv('window.rigidView.frameTimes ? window.rigidView.frameTimes() : null');
  // (NaN too when the page's last 4096 frames do not reach back to the window's start.)
  // (NaN when paused: the page then draws only on change, redraw.js, and skips the rest.)
  let missed = !opt.paused && times && times.length && times[0] <= r0[2] ? 0 : NaN;
  if (!Number.isNaN(missed))
    for (let i = 1; i < times.length; ++i)
      if (times[i - 1] >= r0[2] && times[i] <= r1[2]) missed += Math.max(0, Math.round((times[i] - times[i - 1]) / (1000 / 60)) - 1);
  const decisions = await rv('window.rigidView.renderScaleDecisions ? window.rigidView.renderScaleDecisions() : null');
  // Where the latency goes (pages that split it): publish -> worker -> main thread -> frame.
  const parts = await rv('window.rigidView.latencyParts ? window.rigidView.latencyParts() : null');
  const instances = await rv('window.rigidView.instances()');
  // The page's render scale at the end of the window (its dynamic resolution; 1: full).
  const scale = await rv('window.rigidView.renderScale ? window.rigidView.renderScale() : 1');
  await page.close();
  await stop(view);
  await stop(server);
  if (errors.length) throw new Error(`page errors: ${errors.join(' | ')}`);
  const seconds = (r1[2] - r0[2]) / 1000;
  return { bodies: n, page: webDir || '(default)', path: instances.path || 'instanced',
           meshes: instances.meshes, scale, fps: (r1[0] - r0[0]) / seconds, missed,
           browser_cpu_pct: (100 * (cpu1 - cpu0)) / seconds,
           // The dynamic resolution's decisions since the page loaded (render_scale.js).
           scale_lowered: decisions ? decisions.lowered : NaN, scale_raised: decisions ? decisions.raised : NaN,
           states_per_s: (r1[1] - r0[1]) / seconds, latency_p50_ms: quantile(latencies, 0.5),
           latency_p99_ms: quantile(latencies, 0.99), latency_samples: latencies.length, seconds,
           render_ms: (r1[3] - r0[3]) / Math.max(r1[0] - r0[0], 1),
           state_ms: (r1[4] - r0[4]) / Math.max(r1[1] - r0[1], 1),
           to_worker_p50_ms: parts ? median(parts.toWorker) : NaN,
           to_main_p50_ms: parts ? median(parts.toMain) : NaN,
           to_frame_p50_ms: parts ? median(parts.toFrame) : NaN,
           // States the page received, and those a newer one replaced before a frame applied them
           // (NaN for an older page without these counters: they come back as null).
           received_per_s: r1[5] === null ? NaN : (r1[5] - r0[5]) / seconds,
           skipped_per_s: r1[6] === null ? NaN : (r1[6] - r0[6]) / seconds };
}

// --rigidd-cost (see the top): rigidd and its Stats listener run throughout; the conditions take
// turns, each window after a settling time, so that every condition meets the same machine load.
async function rigiddCost() {
  const n = opt.bodies[0];
  const sceneFile = join(work, `cost_${n}.pbtxt`);
  writeFileSync(sceneFile, sceneText(n));
  const bus = ['--transport', 'dds', '--prefix', `viewcost${process.pid}`];
  const server = start(rigidd, ['--scene', sceneFile, '--mode', 'realtime', ...bus]);
  const listener = start(opt.rigidctl, ['stats', ...bus]);
  // Per Stats report: when it came, its tick lateness p99 (us) and overruns (since start).
  const reports = [];
  let pending = '';
  listener.stdout.on('data', (d) => {
    pending += d;
    const lines = pending.split('\n');
    pending = lines.pop();
    for (const line of lines) {
      const m = line.match(/lateness us: p50 [\d.]+ {2}p99 ([\d.]+) {2}max ([\d.]+) {3}overruns (\d+)/);
      if (m) reports.push({ at: Date.now(), p99: Number(m[1]), max: Number(m[2]), overruns: Number(m[3]) });
    }
  });
  await until('rigidd\'s first Stats', () => reports.length > 0, 30000);
  // Whether its loop runs at real-time priority (root or CAP_SYS_NICE), and how busy the host is.
  console.log(server.err.split('\n').filter((l) => /loop thread|started/.test(l)).join('\n'));
  console.log(`load average at start: ${loadavg().map((x) => x.toFixed(2)).join(', ')}`);
  const conditions = ['no rigid-view', 'rigid-view, no page', 'rigid-view, two pages'];
  const windows = [];
  for (let k = 0; k < opt.repeat; ++k) {
    for (const condition of conditions) {
      let view = null;
      const pages = [];
      if (condition !== 'no rigid-view') {
        view = start(rigidView, [...bus, '--listen', '127.0.0.1:0']);
        const url = await until('rigid-view to print its URL',
                                () => (view.out.match(/http:\/\/127\.0\.0\.1:\d+\//) || [])[0], 30000);
        if (condition === 'rigid-view, two pages') {
          for (let p = 0; p < 2; ++p) {
            const page = await newPage();
            await page.goto(url);
            await until(`${n} bodies drawn`, () => page.evaluate(`window.rigidView.bodies.length === ${n} && window.rigidView.frames >= 2`), 120000);
            pages.push(page);
          }
        }
      }
      await sleep(3000);  // settled: rigid-view joined the bus, the pages compiled their shaders
      const before = reports.length ? reports[reports.length - 1].overruns : 0;
      const from = Date.now();
      const frames0 = await Promise.all(pages.map((p) => p.evaluate('window.rigidView.rendered')));
      await sleep(opt.seconds * 1000);
      const frames1 = await Promise.all(pages.map((p) => p.evaluate('window.rigidView.rendered')));
      const inside = reports.filter((r) => r.at > from + 1000 && r.at <= Date.now());
      for (const page of pages) await page.close();
      if (view) await stop(view);
      if (inside.length < opt.seconds - 3) throw new Error(`${condition}: only ${inside.length} Stats reports in ${opt.seconds} s`);
      const p99s = inside.map((r) => r.p99).sort((a, b) => a - b);
      const w = { condition, reports: inside.length, p99_median_us: quantile(p99s, 0.5),
                  p99_max_us: p99s[p99s.length - 1], lateness_max_us: Math.max(...inside.map((r) => r.max)),
                  overruns: inside[inside.length - 1].overruns - before,
                  page_fps: pages.length ? frames1.map((f, i) => (f - frames0[i]) / opt.seconds) : [] };
      windows.push(w);
      console.log(`window ${windows.length}: ${condition}: tick lateness p99 per second: median ` +
                  `${w.p99_median_us.toFixed(1)} us, max ${w.p99_max_us.toFixed(1)} us; lateness max ` +
                  `${w.lateness_max_us.toFixed(1)} us; overruns ${w.overruns} (${w.reports} Stats)` +
                  (w.page_fps.length ? `; pages ${w.page_fps.map((f) => f.toFixed(1)).join(', ')} frames/s` : ''));
    }
  }
  console.log(`load average at the end: ${loadavg().map((x) => x.toFixed(2)).join(', ')}`);
  await stop(listener);
  await stop(server);
  console.log(`rigidd ${opt.rate} Hz realtime, ${n} bodies, state every ${opt.publishEvery} ticks; ` +
              `medians over ${opt.repeat} windows of ${opt.seconds} s per condition:`);
  for (const condition of conditions) {
    const ws = windows.filter((w) => w.condition === condition);
    const m = (key) => median(ws.map((w) => w[key]));
    console.log(`  ${condition}: tick lateness p99 (median of the seconds) ${m('p99_median_us').toFixed(1)} us, ` +
                `worst second's p99 ${m('p99_max_us').toFixed(1)} us, lateness max ${m('lateness_max_us').toFixed(1)} us, ` +
                `overruns per window ${m('overruns')}`);
  }
}

try {
  const flags = opt.chromiumFlags || [];
  const chromiumArgs = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                        '--disable-background-networking', '--disable-component-update', '--disable-sync',
                        '--use-angle=swiftshader', '--enable-unsafe-swiftshader', ...flags.filter((f) => f[0] !== '!')]
    .filter((f) => !flags.includes(`!${f}`));
  if (opt.browserCpus && opt.driver !== 'cdp') usage('--browser-cpus: only with --driver cdp');
  browser = opt.driver === 'cdp'
    ? (opt.browserCpus ? await launchCdp('/usr/bin/taskset', ['-c', opt.browserCpus, '/usr/bin/chromium', ...chromiumArgs])
                       : await launchCdp('/usr/bin/chromium', chromiumArgs))
    : await chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, chromiumSandbox: false,
                              args: chromiumArgs });
  if (costMode) {
    await rigiddCost();
    clearTimeout(watchdog);
    await cleanup();
    process.exit(0);
  }
  const results = [];
  // Interleaved (size, page) pairs: every page meets the same machine load, run after run.
  for (let k = 0; k < opt.repeat; ++k) {
    for (const n of opt.bodies) {
      for (const webDir of opt.webDirs) {
        const r = await run(n, webDir);
        results.push(r);
        console.log(`${n} bodies, page ${r.page} (${r.meshes} ${r.path} meshes, render scale ` +
                    `${r.scale.toFixed(2)} at the end, lowered ${r.scale_lowered}, raised ` +
                    `${r.scale_raised})${opt.paused ? ', paused' : ''}: ${r.fps.toFixed(1)} frames/s (${r.missed} refreshes missed), ` +
                    `Chromium ${r.browser_cpu_pct.toFixed(0)}% CPU, ` +
                    `${r.states_per_s.toFixed(1)} states/s drawn, latency publish -> frame ` +
                    `p50 ${r.latency_p50_ms.toFixed(1)} ms, p99 ${r.latency_p99_ms.toFixed(1)} ms ` +
                    `(${r.latency_samples} states, ${r.seconds.toFixed(1)} s; p50 to the worker ` +
                    `${r.to_worker_p50_ms.toFixed(1)}, to the main thread ${r.to_main_p50_ms.toFixed(1)}, ` +
                    `to the frame ${r.to_frame_p50_ms.toFixed(1)} ms; ${r.received_per_s.toFixed(1)} states/s ` +
                    `received, ${r.skipped_per_s.toFixed(1)} skipped); per frame: render ` +
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
        console.log(`  ${n} bodies, page ${rs[0].page}: ${m('fps')} frames/s (${m('missed')} refreshes missed), Chromium ${m('browser_cpu_pct')}% CPU, ${m('states_per_s')} states/s, ` +
                    `latency p50 ${m('latency_p50_ms')} ms, p99 ${m('latency_p99_ms')} ms ` +
                    `(to the worker ${m('to_worker_p50_ms')}, main thread ${m('to_main_p50_ms')}, frame ${m('to_frame_p50_ms')})`);
      }
    }
  }
  if (opt.csv) {
    const header = 'bodies,page,path,meshes,scale,fps,states_per_s,latency_p50_ms,latency_p99_ms,latency_samples,seconds,render_ms,state_ms,to_worker_p50_ms,to_main_p50_ms,to_frame_p50_ms\n';
    if (!existsSync(opt.csv)) writeFileSync(opt.csv, header);
    for (const r of results)
      appendFileSync(opt.csv, `${r.bodies},${r.page},${r.path},${r.meshes},${r.scale},${r.fps},${r.states_per_s},${r.latency_p50_ms},${r.latency_p99_ms},${r.latency_samples},${r.seconds},${r.render_ms},${r.state_ms},${r.to_worker_p50_ms},${r.to_main_p50_ms},${r.to_frame_p50_ms}\n`);
  }
  clearTimeout(watchdog);
  await cleanup();
} catch (e) {
  console.error(`view_bench: ${e.message}`);
  for (const c of processes.children) if (c.err) console.error(`--- ${c.spawnargs[0]} stderr:\n${c.err.slice(-2000)}`);
  await cleanup();
  process.exit(1);
}

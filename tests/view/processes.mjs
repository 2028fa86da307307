// The child processes a browser test or bench/view starts (rigidd, rigid-view, rigid-record,
// rigidctl): each started with the test's environment, its output kept for the failure message,
// and every one still running stopped by PID (SIGTERM) when the test ends or fails, so that none
// outlives it. Also the bounded waits they all use.
import { spawn } from 'node:child_process';
import { fileURLToPath } from 'node:url';

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Polls `check` every `every` ms until it returns something truthy (returned), or throws after
// `ms` ms naming `what`.
export async function until(what, check, ms, every = 50) {
  const end = Date.now() + ms;
  for (;;) {
    const v = await check();
    if (v) return v;
    if (Date.now() > end) throw new Error(`timed out waiting for ${what}`);
    await sleep(every);
  }
}

// The environment for DDS processes: ctest sets CYCLONEDDS_URI; by hand, the source tree's
// loopback config (never Cyclone's default interface).
export function loopbackEnv() {
  const config = fileURLToPath(new URL('../../config/cyclonedds.xml', import.meta.url));
  return { ...process.env, CYCLONEDDS_URI: process.env.CYCLONEDDS_URI || `file://${config}` };
}

export class Processes {
  constructor(env = loopbackEnv()) {
    this.env = env;
    this.children = [];
  }

  // child.out and child.err accumulate its output; child.done resolves to its exit code.
  start(exe, args) {
    const child = spawn(exe, args, { env: this.env, stdio: ['ignore', 'pipe', 'pipe'] });
    child.out = '';
    child.err = '';
    child.stdout.on('data', (d) => { child.out += d; });
    child.stderr.on('data', (d) => { child.err += d; });
    child.done = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
    this.children.push(child);
    return child;
  }

  // The exit code, or 'timeout' if it is still running after `ms`.
  static exited(child, ms) {
    return Promise.race([child.done, sleep(ms).then(() => 'timeout')]);
  }

  // SIGTERM to one child, then up to 5 s for it to exit.
  async stop(child) {
    if (child.exitCode === null && child.signalCode === null) child.kill('SIGTERM');
    await Processes.exited(child, 5000);
  }

  // SIGTERM to every child still running (no wait: the caller is on its way out).
  stopAll() {
    for (const c of this.children) if (c.exitCode === null && c.signalCode === null) c.kill('SIGTERM');
  }

  // Every child's command line and stderr, for a failure message.
  stderrs() {
    return this.children.map((c) => `--- ${c.spawnargs.join(' ')} stderr:\n${c.err}`).join('\n');
  }
}

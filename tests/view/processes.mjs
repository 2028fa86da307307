// The child processes a browser test or bench/view starts (rigidd, rigid-view, rigid-record,
// rigidctl): each started with the test's environment, its output kept for the failure message,
// and every one still running stopped by PID (SIGTERM) when the test ends or fails, so that none
// outlives it. Also the bounded waits they all use.
import { spawn } from 'node:child_process';
import { rmSync } from 'node:fs';
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

  // child.out and child.err accumulate its output; child.done resolves to its exit code (-1 if it
  // could not be started).
  start(exe, args) {
    const child = spawn(exe, args, { env: this.env, stdio: ['ignore', 'pipe', 'pipe'] });
    child.out = '';
    child.err = '';
    child.stdout.on('data', (d) => { child.out += d; });
    child.stderr.on('data', (d) => { child.err += d; });
    child.done = new Promise((resolve) => {
      child.on('exit', (code) => resolve(code));
      // Not started at all (no such executable): said in its stderr, exit code -1.
      child.on('error', (e) => { child.err += `cannot start ${exe}: ${e.message}\n`; resolve(-1); });
    });
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

// A browser test's way out: `fail(message)` prints the message, the page's console errors and
// every child's stderr, then closes the browser, stops the children, removes `tempDir` and exits
// 1; `cleanup()` does the same without the report (the passing path). A watchdog fails the test
// after `seconds`. Set `harness.browser` once the browser is launched.
export function browserHarness(processes, tempDir, seconds) {
  const harness = {
    browser: null,
    consoleErrors: [],
    async cleanup() {
      if (harness.browser) await harness.browser.close().catch(() => {});
      processes.stopAll();
      rmSync(tempDir, { recursive: true, force: true });
    },
    // Collects a page's console errors and uncaught exceptions (the tests require none).
    watch(page) {
      page.on('console', (m) => { if (m.type() === 'error') harness.consoleErrors.push(m.text()); });
      page.on('pageerror', (e) => harness.consoleErrors.push(String(e)));
      return page;
    },
    fail(message) {
      console.error(`FAIL: ${message}`);
      if (harness.consoleErrors.length) console.error(`console errors: ${harness.consoleErrors.join(' | ')}`);
      console.error(processes.stderrs());
      harness.cleanup().finally(() => process.exit(1));
    },
  };
  harness.deadline = setTimeout(() => harness.fail(`took more than ${seconds} s`), seconds * 1000);
  return harness;
}

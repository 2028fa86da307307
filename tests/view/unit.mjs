// A minimal runner for the page's modules tested in node (render_scale_test.mjs, redraw_test.mjs,
// protocol_test.mjs): test(name, body) runs body and prints ok or FAIL with the stack; done() exits
// non-zero if any failed.
let failures = 0;

export function test(name, body) {
  try {
    body();
    console.log(`ok   ${name}`);
  } catch (e) {
    ++failures;
    console.log(`FAIL ${name}\n${e.stack}`);
  }
}

export function done() {
  if (failures) {
    console.log(`${failures} failed`);
    process.exit(1);
  }
  console.log('all passed');
}

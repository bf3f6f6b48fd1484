// End-to-end test of `vitro view SCENARIO --foxglove` with Foxglove's own WebSocket client
// (npm @foxglove/ws-protocol's FoxgloveClient over the `ws` package).
//
//   node scripts/e2e_foxglove.mjs --vitro target/debug/vitro --modules DIR
//        [--scenario scenarios/evacuation.toml] [--timeout 120]
//
// Starts the live view with the Foxglove server on a free loopback port, connects, subscribes
// to every channel it advertises (those advertised later included), and passes when each has
// delivered at least one message that decodes as JSON and has its schema's required fields,
// every message of a Foxglove type (foxglove.SceneUpdate, ...) is valid against Foxglove's
// official JSON Schema for it (npm @foxglove/schemas, checked with ajv), and the server's
// clock (the `time` capability) has ticked. Then: the `paused` parameter
// pauses and resumes the run, the page viewer's WebSocket serves the same run meanwhile, and a
// handshake naming a foreign Host gets 403. DIR holds node_modules with @foxglove/ws-protocol,
// @foxglove/schemas, ajv and ws. scripts/e2e_foxglove.sh installs them and runs this. Exit code 0 when all pass.

import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';
import { createInterface } from 'node:readline';

const args = Object.fromEntries(
  process.argv.slice(2).reduce((acc, a, i, all) => (a.startsWith('--') ? [...acc, [a.slice(2), all[i + 1]]] : acc), []),
);
const vitro = resolve(args.vitro || 'target/debug/vitro');
const scenario = args.scenario || 'scenarios/evacuation.toml';
const limitS = Number(args.timeout || 120);
const require = createRequire(join(resolve(args.modules || '.'), 'package.json'));
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const WebSocket = require('ws');
const official = require('@foxglove/schemas/dist/jsonschema');
const Ajv = require('ajv');
const ajv = new Ajv({ strict: false });
/** Foxglove's own schema for a `foxglove.X` schema name, compiled; null for others. */
const validators = new Map();
function officialValidator(name) {
  if (!validators.has(name)) {
    const schema = name.startsWith('foxglove.') ? official[name.slice('foxglove.'.length)] : null;
    validators.set(name, schema ? ajv.compile(schema) : null);
  }
  return validators.get(name);
}

const started = Date.now();
let failures = 0;
const log = (msg) => console.log(`[${((Date.now() - started) / 1000).toFixed(1)} s] ${msg}`);
function check(ok, what) {
  log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures += 1;
}

const child = spawn(vitro, ['view', scenario, '--addr', '127.0.0.1:0', '--speed', '20', '--foxglove', '127.0.0.1:0'], {
  stdio: ['ignore', 'pipe', 'inherit'],
});
const timer = setTimeout(() => {
  log(`FAIL not done within ${limitS} s`);
  child.kill();
  process.exit(1);
}, limitS * 1000);

/** The page's and the Foxglove server's addresses, from the lines `vitro view` prints. */
const addresses = new Promise((res, rej) => {
  const found = {};
  createInterface({ input: child.stdout }).on('line', (line) => {
    const page = line.match(/serving (http:\/\/\S+)\//);
    const fox = line.match(/serving Foxglove (ws:\/\/\S+)/);
    if (page) found.page = page[1];
    if (fox) found.foxglove = fox[1];
    if (!page && !fox) log(`vitro: ${line}`);
    if (found.page && found.foxglove) res(found);
  });
  child.on('exit', (code) => rej(new Error(`vitro view exited with ${code}`)));
});

/** Resolves when `pred()` holds (polled), or rejects after `ms`. */
function until(pred, ms, what) {
  return new Promise((res, rej) => {
    const t0 = Date.now();
    const poll = setInterval(() => {
      if (pred()) {
        clearInterval(poll);
        res();
      } else if (Date.now() - t0 > ms) {
        clearInterval(poll);
        rej(new Error(`timed out waiting for ${what}`));
      }
    }, 20);
  });
}

async function foxglove(url) {
  const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
  const channels = new Map(); // channel id -> { topic, schemaName, required, count }
  const bySub = new Map();
  const decoder = new TextDecoder();
  let info = null;
  let ticks = 0;
  let lastTime = -1n;
  let params = null;
  client.on('error', (e) => log(`client error: ${e.message ?? e}`));
  client.on('serverInfo', (i) => (info = i));
  client.on('status', (s) => log(`server status: ${JSON.stringify(s)}`));
  client.on('advertise', (list) => {
    for (const c of list) {
      let required = [];
      try {
        required = JSON.parse(c.schema).required ?? [];
      } catch (e) {
        check(false, `${c.topic}: schema is JSON (${e.message})`);
      }
      channels.set(c.id, { ...c, required, count: 0 });
      bySub.set(client.subscribe(c.id), c.id);
    }
  });
  client.on('message', ({ subscriptionId, timestamp, data }) => {
    const c = channels.get(bySub.get(subscriptionId));
    const text = decoder.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    let msg;
    try {
      msg = JSON.parse(text);
    } catch (e) {
      check(false, `${c.topic}: message is JSON (${e.message})`);
      return;
    }
    const missing = c.required.filter((k) => !(k in msg));
    const validate = officialValidator(c.schemaName);
    const valid = !validate || validate(msg);
    if (c.count === 0) {
      const verdict = validate ? ', valid against the official schema' : '';
      check(missing.length === 0 && valid, `${c.topic} (${c.schemaName}): first message at t=${Number(timestamp) / 1e9} s decodes${verdict}${missing.length ? `; lacks ${missing}` : ''}`);
    } else if (!valid && !c.invalid) {
      check(false, `${c.topic}: a message is invalid against the official schema`);
    }
    if (!valid && !c.invalid) {
      c.invalid = true;
      log(`  ${JSON.stringify(validate.errors.slice(0, 3))}`);
    }
    c.count += 1;
  });
  client.on('time', ({ timestamp }) => {
    if (timestamp < lastTime) check(false, `server time went back: ${lastTime} -> ${timestamp}`);
    lastTime = timestamp;
    ticks += 1;
  });
  client.on('parameterValues', (p) => (params = p));

  await until(() => info && channels.size > 0, 20000, 'serverInfo and advertise');
  check(info.capabilities.includes('time') && info.capabilities.includes('parameters'), `serverInfo "${info.name}": ${info.capabilities}`);
  await until(() => ticks > 0 && [...channels.values()].every((c) => c.count > 0), 60000, 'a message on every channel');
  check(true, `every advertised channel (${channels.size}) delivered; ${ticks} time updates, sim time ${Number(lastTime) / 1e9} s`);

  client.setParameters([{ name: 'paused', value: true }], 'pause');
  await until(() => params?.id === 'pause', 10000, 'the pause answer');
  check(params.parameters[0].value === true, 'setParameters paused=true pauses the run');
  await new Promise((r) => setTimeout(r, 300));
  const frozen = lastTime;
  await new Promise((r) => setTimeout(r, 500));
  check(lastTime === frozen, `paused: the clock stays at ${Number(frozen) / 1e9} s`);
  client.setParameters([{ name: 'paused', value: false }], 'resume');
  await until(() => params?.id === 'resume', 10000, 'the resume answer');
  await until(() => lastTime > frozen, 10000, 'the clock to move again');
  check(true, 'setParameters paused=false resumes the run');
  client.close();
}

/** The page viewer's WebSocket serves the same run: a frame comes. */
async function page(url) {
  const ws = new WebSocket(`${url.replace('http', 'ws')}/ws`);
  let frame = null;
  ws.on('message', (m) => {
    const v = JSON.parse(m.toString());
    if (v.type === 'frame') frame = v.frame;
  });
  await until(() => frame, 20000, 'a page frame');
  check(frame.entities.length > 0, `the page viewer serves the same run alongside (t=${frame.t_ns / 1e9} s)`);
  ws.close();
}

/** A handshake whose Host names another site gets 403. */
function foreignHost(url) {
  const port = new URL(url).port;
  return new Promise((res) => {
    const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], { headers: { Host: `evil.example:${port}` } });
    ws.on('unexpected-response', (_req, r) => res(r.statusCode));
    ws.on('open', () => res(101));
    ws.on('error', () => res(0));
  }).then((code) => check(code === 403, `Host evil.example:${port} gets ${code}`));
}

try {
  const { page: pageUrl, foxglove: foxUrl } = await addresses;
  log(`${scenario}: page ${pageUrl}, Foxglove ${foxUrl}`);
  await foxglove(foxUrl);
  await page(pageUrl);
  await foreignHost(foxUrl);
} catch (e) {
  check(false, e.message);
}
clearTimeout(timer);
child.kill();
log(failures ? `${failures} check(s) failed` : 'all checks passed');
process.exit(failures ? 1 : 0);

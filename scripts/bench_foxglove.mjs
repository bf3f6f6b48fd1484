// What serving a live run to Foxglove costs: the CPU time of `vitro view` per event, with no
// client and with a Foxglove client subscribed to every channel, side by side.
//
//   node scripts/bench_foxglove.mjs --vitro target/release/vitro --modules DIR
//        [--scenario scenarios/evacuation.toml] [--speed 1000] [--repeat 3]
//
// Each run is `vitro view SCENARIO --speed X` (with `--foxglove` and a client, or without);
// the CPU time of the process (user + system, /proc/PID/stat) from the line announcing the
// server (the scenario built) to the line announcing the end of the run, divided by the
// events fired. Prints one line per run, the medians and their ratio. DIR holds
// node_modules with @foxglove/ws-protocol and ws (scripts/e2e_foxglove.sh installs them).

import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';
import { createInterface } from 'node:readline';

const args = Object.fromEntries(
  process.argv.slice(2).reduce((acc, a, i, all) => (a.startsWith('--') ? [...acc, [a.slice(2), all[i + 1]]] : acc), []),
);
const vitro = resolve(args.vitro || 'target/release/vitro');
const scenario = args.scenario || 'scenarios/evacuation.toml';
const speed = args.speed || '1000';
const repeat = Number(args.repeat || 3);
const require = createRequire(join(resolve(args.modules || '.'), 'package.json'));
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const WebSocket = require('ws');
const TICKS = 100; // USER_HZ on Linux

/** CPU seconds (user + system) the process `pid` has used. */
function cpu(pid) {
  const fields = readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / TICKS;
}

/** One run; resolves to { events, cpu, messages }. */
function once(foxglove) {
  const extra = foxglove ? ['--foxglove', '127.0.0.1:0'] : [];
  const child = spawn(vitro, ['view', scenario, '--addr', '127.0.0.1:0', '--speed', speed, ...extra], {
    stdio: ['ignore', 'pipe', 'inherit'],
  });
  let start = null;
  let messages = 0;
  let client = null;
  return new Promise((res, rej) => {
    createInterface({ input: child.stdout }).on('line', (line) => {
      const fox = line.match(/serving Foxglove (ws:\/\/\S+)/);
      const page = line.match(/^serving http/);
      const end = line.match(/after (\d+) events/);
      if ((page && !foxglove) || fox) start = cpu(child.pid);
      if (fox) {
        client = new FoxgloveClient({ ws: new WebSocket(fox[1], [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
        client.on('advertise', (cs) => cs.forEach((c) => client.subscribe(c.id)));
        client.on('message', () => (messages += 1));
      }
      if (end) {
        const used = cpu(child.pid) - start;
        client?.close();
        child.kill();
        res({ events: Number(end[1]), cpu: used, messages });
      }
    });
    child.on('exit', (code) => rej(new Error(`vitro view exited with ${code}`)));
  });
}

const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
const perEvent = { without: [], with: [] };
for (let i = 0; i < repeat; i += 1) {
  for (const foxglove of [false, true]) {
    const r = await once(foxglove);
    const us = (r.cpu / r.events) * 1e6;
    perEvent[foxglove ? 'with' : 'without'].push(us);
    console.log(`${foxglove ? 'with a Foxglove client' : 'no client            '}: ${r.events} events, ${r.cpu.toFixed(2)} s CPU, ${us.toFixed(2)} us/event${foxglove ? `, ${r.messages} messages received` : ''}`);
  }
}
const a = median(perEvent.without);
const b = median(perEvent.with);
console.log(`median: ${a.toFixed(2)} us/event without, ${b.toFixed(2)} with; ratio ${(b / a).toFixed(3)}`);

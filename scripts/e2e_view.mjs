// End-to-end test of `vitro view` in a real browser (headless Chromium via playwright-core).
//
//   node scripts/e2e_view.mjs --vitro target/debug/vitro --modules DIR [--screenshots docs]
//        [--scenario scenarios/evacuation.toml]
//
// Live (the evacuation mission): the clock advances; speed changes take effect; pause
// freezes it; each step advances it by exactly one event; clicking an entity opens the
// inspector with its state; the 2D and 3D screenshots are not blank. Replay (a recording
// made with `vitro run --record`): the timeline seeks forwards and back, a step shows the
// next frame. DIR holds node_modules/playwright-core; with --screenshots the two views are
// saved as view-2d.png and view-3d.png there. Exit code 0 when every check passes.
// scripts/e2e_view.sh installs what this needs and runs it.

import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { createInterface } from 'node:readline';
import { checkNotBlank, clockOf, waitFor } from './e2e_view_lib.mjs';

const args = Object.fromEntries(
  process.argv.slice(2).reduce((acc, a, i, all) => (a.startsWith('--') ? [...acc, [a.slice(2), all[i + 1]]] : acc), []),
);
const vitro = resolve(args.vitro || 'target/debug/vitro');
const scenario = args.scenario || 'scenarios/evacuation.toml';
const modules = resolve(args.modules || '.');
const chromiumPath = args.chromium || '/usr/bin/chromium';
const shots = args.screenshots ? resolve(args.screenshots) : null;
const { chromium } = createRequire(join(modules, 'package.json'))('playwright-core');

const started = Date.now();
const servers = [];
let failures = 0;

function log(msg) {
  console.log(`[${((Date.now() - started) / 1000).toFixed(1)} s] ${msg}`);
}

function check(ok, what) {
  if (ok) {
    log(`ok   ${what}`);
  } else {
    failures += 1;
    log(`FAIL ${what}`);
  }
}

/** Starts `vitro view ARGS` on a free port; resolves to its URL. */
function serve(viewArgs) {
  const child = spawn(vitro, ['view', ...viewArgs, '--addr', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  servers.push(child);
  return new Promise((res, rej) => {
    const lines = createInterface({ input: child.stdout });
    lines.on('line', (line) => {
      const m = line.match(/serving (http:\/\/\S+)/);
      if (m) res(m[1]);
      else log(`vitro: ${line}`);
    });
    child.on('exit', (code) => rej(new Error(`vitro view exited with ${code}`)));
  });
}

async function open(browser, url) {
  const page = await browser.newPage({ viewport: { width: 1400, height: 860 } });
  page.on('pageerror', (e) => {
    failures += 1;
    log(`FAIL page error: ${e.message}`);
  });
  await page.goto(url);
  await waitFor(page, () => window.vitro && window.vitro.state.scene && window.vitro.state.frame, 20000);
  return page;
}

async function live(browser) {
  const url = await serve([scenario, '--speed', '1']);
  log(`live view of ${scenario} at ${url}`);
  const page = await open(browser, url);

  const a = await clockOf(page);
  await page.waitForTimeout(1500);
  const b = await clockOf(page);
  check(b.t > a.t && b.text !== a.text, `the clock advances (${a.text} -> ${b.text})`);
  // The calendar time beside it: the scenario's start (2024-06-01T06:00:00Z) plus the clock.
  const wall = await page.textContent('#wall');
  check(/^2024-06-01 06:\d\d:\d\d UTC$/.test(wall), `the calendar clock shows the mission's date (${wall})`);

  // Speed: 1x, then + three times (2x, 5x, 10x); compare simulated seconds per wall second.
  const rate = async () => {
    const c0 = await clockOf(page);
    const w0 = Date.now();
    await page.waitForTimeout(2500);
    const c1 = await clockOf(page);
    return (c1.t - c0.t) / 1e9 / ((Date.now() - w0) / 1000);
  };
  const slow = await rate();
  for (let i = 0; i < 3; i++) {
    const before = await page.textContent('#speed');
    await page.click('#faster');
    await waitFor(page, (s) => document.getElementById('speed').textContent !== s, 5000, before);
  }
  const speedText = await page.textContent('#speed');
  const fast = await rate();
  check(slow > 0.5 && slow < 1.6, `at 1x the run goes at ${slow.toFixed(2)} simulated s per wall s`);
  check(speedText === '10×' && fast > 5 * slow, `at ${speedText} it goes at ${fast.toFixed(2)} (x${(fast / slow).toFixed(1)})`);

  // Pause freezes the clock.
  await page.click('#play');
  await waitFor(page, () => document.getElementById('play').textContent === 'Resume', 5000);
  await page.waitForTimeout(400);
  const p0 = await clockOf(page);
  await page.waitForTimeout(1200);
  const p1 = await clockOf(page);
  check(p0.t === p1.t && p0.events === p1.events, `pause freezes the clock at ${p0.text}, ${p0.events} events`);

  // Each step fires exactly one event.
  let ev = p1.events;
  for (let k = 0; k < 3; k++) {
    await page.click('#step');
    await waitFor(page, (e) => Number(document.getElementById('events').dataset.events) !== e, 5000, ev);
    await page.waitForTimeout(600);
    const s = await clockOf(page);
    check(s.events === ev + 1, `step ${k + 1}: ${ev} -> ${s.events} events (${s.text})`);
    ev = s.events;
  }

  // Clicking an entity opens the inspector with its state.
  const target = await page.evaluate(() => {
    const es = [...window.vitro.state.byId.values()];
    const e = es.find((x) => x.kind === 'truck') || es[0];
    return { id: e.id, name: e.name, x: e.pos[0].toFixed(1), p: window.vitro.screenPos(e.id) };
  });
  await page.mouse.click(target.p.x, target.p.y);
  await waitFor(page, (n) => (document.getElementById('inspected-name') || {}).textContent === n, 5000, target.name);
  const inspector = await page.textContent('#inspector');
  check(inspector.includes(target.name) && inspector.includes(target.x) && inspector.includes('status'), `clicking ${target.name} shows its state in the inspector`);

  // Let the mission get going (the truck on its way to the extraction point), then the
  // pictures, the truck selected (its plan drawn).
  await page.evaluate(() => window.vitro.send({ cmd: 'speed', factor: 50 }));
  await page.click('#play');
  await waitFor(page, () => Number(document.getElementById('clock').dataset.tNs) > 270e9, 60000);
  await page.click('#play');
  await waitFor(page, () => document.getElementById('play').textContent === 'Resume', 5000);
  await page.evaluate(() => {
    const v = window.vitro;
    const ps = [...v.state.byId.values()].filter((e) => e.status !== 'undetected').map((e) => e.pos);
    const xs = ps.map((p) => p[0]);
    const ys = ps.map((p) => p[1]);
    const m = 150;
    v.box = [Math.min(...xs) - m, Math.min(...ys) - m, Math.max(...xs) + m, Math.max(...ys) + m];
    v.map.fitTo(v.box, document.getElementById('legend').offsetHeight + 16);
  });
  await page.waitForTimeout(500);
  const png2d = await page.screenshot();
  check(await checkNotBlank(page, png2d, '2D'), '2D screenshot is not blank');
  await page.click('#tab3d');
  // in 3D, the neighbourhood of the truck
  await page.evaluate((id) => {
    const [x, y] = window.vitro.state.byId.get(id).pos;
    window.vitro.view3d.lookAtBox([x - 380, y - 300, x + 380, y + 460]);
  }, target.id);
  await page.waitForTimeout(2500);
  const png3d = await page.screenshot();
  const box = await page.locator('#view3d').boundingBox();
  check(await checkNotBlank(page, png3d, '3D', box), '3D screenshot is not blank (WebGL drew the scene)');
  if (shots) {
    writeFileSync(join(shots, 'view-2d.png'), png2d);
    writeFileSync(join(shots, 'view-3d.png'), png3d);
    log(`screenshots written to ${shots}`);
  }
  await page.close();
}

async function replay(browser) {
  const dir = mkdtempSync(join(tmpdir(), 'vitro-e2e-'));
  const file = join(dir, 'run.mcap');
  // Ten simulated minutes are enough to seek in (the debug build records about 30 s a second).
  const rec = spawnSync(vitro, ['run', scenario, '--until', '600', '--record', file, '--quiet'], { encoding: 'utf8' });
  // 0: mission success, 4: mission failed; either way the run was recorded.
  if (rec.status !== 0 && rec.status !== 4) throw new Error(`vitro run --record failed: ${rec.stderr}`);
  const url = await serve([file]);
  log(`replay of ${file} at ${url}`);
  const page = await open(browser, url);
  const hello = await page.evaluate(() => window.vitro.state.hello);
  check(hello.mode === 'replay' && (await page.isVisible('#timeline')), 'replay mode shows a timeline');
  const seek = async (fraction) => {
    await page.$eval('#timeline', (el, v) => {
      el.value = String(v);
      el.dispatchEvent(new Event('input'));
      el.dispatchEvent(new Event('change'));
    }, Math.round(fraction * 1000));
    const want = hello.start_ns + fraction * (hello.end_ns - hello.start_ns);
    // the frame at or just before the target (frames every sample period, <= 5 s here)
    await waitFor(page, (w) => {
      const t = Number(document.getElementById('clock').dataset.tNs);
      return t <= w + 2e9 && t > w - 5e9;
    }, 10000, want);
    return clockOf(page);
  };
  await page.click('#play');
  await waitFor(page, () => document.getElementById('play').textContent === 'Resume', 5000);
  const late = await seek(0.75);
  const early = await seek(0.2);
  check(late.t > early.t && early.t > hello.start_ns, `the timeline seeks forwards (${late.text}) and back (${early.text})`);
  await page.click('#step');
  await waitFor(page, (t) => Number(document.getElementById('clock').dataset.tNs) > t, 5000, early.t);
  const next = await clockOf(page);
  check(next.t > early.t && next.t - early.t < 10e9, `step shows the next frame (${early.text} -> ${next.text})`);
  await page.close();
  rmSync(dir, { recursive: true, force: true });
}

let browser;
try {
  browser = await chromium.launch({
    executablePath: chromiumPath,
    args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--enable-unsafe-swiftshader'],
  });
  await live(browser);
  await replay(browser);
} catch (e) {
  failures += 1;
  log(`FAIL ${e.stack || e}`);
} finally {
  if (browser) await browser.close();
  for (const s of servers) s.kill();
}
log(failures ? `${failures} check(s) failed` : 'every check passed');
process.exit(failures ? 1 : 0);

#!/usr/bin/env node
// Browser test of the mission control display (docs/mission_control.md):
// drives Debian's Chromium (puppeteer-core, no browser download) against a
// running rse-ground serve and checks what the operator sees.
//
//   node unit_test/ground/mission_control/web/display_test.mjs --url http://127.0.0.1:8090/ \
//        [--live] [--history --interval START_MS:END_MS] [--screenshot build/mission_control/display.png]
//
// Live checks (the default, with a mission sending telemetry): each plot of
// the mission overview draws points and newer ones keep coming (its legend,
// expanded and hovered at the plot's right end as a user would, shows the
// newest point's time, and that time advances); realtime datums reach an
// openmct.telemetry.subscribe made in the page; the event log shows rows; the
// map draws the plan and the driven track (rse-map-plan, rse-map-track with
// non-empty geometry) and every rock of /api/map; the drive-health panel shows
// six wheels with data; the mission-state panel shows the mode.
//
// History checks (--history, after a server restart; --interval is the past
// interval to ask for, default the last 15 minutes): inside the page,
// openmct.telemetry.request of ROVER_STATE, DRIVES and HK (--history-packets)
// over the interval returns archived datums, oldest first, all inside it; then
// with the time conductor fixed on the interval the map draws the archived
// track and the position plot shows a point inside the interval.
//
// Each check prints PASS or FAIL; the last line is "N passed, N failed"; the
// exit status is 1 when a check failed (2 for bad arguments). The screenshot
// of the page as the checks left it is saved where --screenshot says.

import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const repoDir = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../../..');
const webDir = path.join(repoDir, 'ground/mission_control/web');
// puppeteer-core is installed with the display's npm packages (make mission-control-deps).
let puppeteer;
try {
  puppeteer = createRequire(path.join(webDir, 'package.json'))('puppeteer-core');
} catch (error) {
  console.error(`display_test: puppeteer-core not found under ${webDir}/node_modules (make mission-control-deps): ${error.message}`);
  process.exit(2);
}

function usage(message) {
  console.error(`display_test: ${message}`);
  console.error(
    'usage: display_test.mjs --url URL [--live] [--history [--interval START_MS:END_MS] [--history-packets A,B] [--min-points N]]' +
      ' [--screenshot FILE] [--timeout-ms MS] [--chromium PATH]'
  );
  process.exit(2);
}

function parseArgs(argv) {
  const a = {
    url: process.env.RSE_MC_URL,
    live: false,
    history: false,
    interval: undefined,
    historyPackets: ['ROVER_STATE', 'DRIVES', 'HK'],
    minPoints: 1,
    screenshot: process.env.RSE_MC_SCREENSHOT || 'build/mission_control/display_test.png',
    timeoutMs: 45000,
    chromium: process.env.CHROMIUM || '/usr/bin/chromium'
  };
  for (let i = 0; i < argv.length; i++) {
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${argv[i]} needs a value`));
    switch (argv[i]) {
      case '--url': a.url = value(); break;
      case '--live': a.live = true; break;
      case '--history': a.history = true; break;
      case '--interval': {
        const [start, end] = value().split(':').map(Number);
        if (!(Number.isFinite(start) && Number.isFinite(end) && start < end)) usage('--interval START_MS:END_MS, START < END');
        a.interval = { start, end };
        break;
      }
      case '--history-packets': a.historyPackets = value().split(',').filter(Boolean); break;
      case '--min-points': a.minPoints = Number(value()); break;
      case '--screenshot': a.screenshot = value(); break;
      case '--timeout-ms': a.timeoutMs = Number(value()); break;
      case '--chromium': a.chromium = value(); break;
      default: usage(`unknown argument ${argv[i]}`);
    }
  }
  if (!a.url) usage('no --url (or RSE_MC_URL)');
  if (!a.live && !a.history) a.live = true;
  if (a.history && !a.interval) a.interval = { start: Date.now() - 15 * 60 * 1000, end: Date.now() };
  return a;
}

const args = parseArgs(process.argv.slice(2));
const results = [];

function record(name, ok, detail = '') {
  results.push({ name, ok });
  console.log(`${ok ? 'PASS' : 'FAIL'} ${name}${detail ? `: ${detail}` : ''}`);
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// Polls probe() until accept(value) or the timeout; returns the last value.
async function waitFor(probe, accept, timeoutMs = args.timeoutMs, everyMs = 500) {
  const deadline = Date.now() + timeoutMs;
  let value;
  for (;;) {
    try {
      value = await probe();
    } catch (error) {
      value = { error: error.message };
    }
    if (accept(value) || Date.now() >= deadline) return value;
    await sleep(everyMs);
  }
}

// "2026-12-03 06:14:53.200Z" (Open MCT's utc format) -> ms.
function parseUtc(text) {
  const ms = Date.parse(String(text).trim().replace(' ', 'T'));
  return Number.isFinite(ms) ? ms : undefined;
}

function iso(ms) {
  return new Date(ms).toISOString();
}

// The frames of the open Flexible Layout, by their title.
async function frames(page) {
  const handles = await page.$$('.c-fl-frame__drag-wrapper');
  const out = [];
  for (const handle of handles) {
    const name = await handle.$eval('.c-object-label__name', (e) => e.textContent.trim()).catch(() => '');
    out.push({ name, handle });
  }
  return out;
}

async function frameNamed(page, name) {
  return (await frames(page)).find((f) => f.name === name)?.handle;
}

// What the plot's legend shows with the cursor at the chart's right end:
// [{name, time}] with the time of the point nearest the cursor per series.
async function hoveredLegend(page, frame) {
  if (!(await frame.$('tr.plot-legend-item'))) {
    const control = await frame.$('.c-plot-legend__view-control');
    if (control) await control.click();
    await sleep(300);
  }
  const area = await frame.$('.gl-plot-chart-area');
  const box = area && (await area.boundingBox());
  if (!box) return [];
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.move(box.x + box.width - 2, box.y + box.height / 2, { steps: 3 });
  await sleep(400);
  const rows = await frame.$$eval('tr.plot-legend-item', (items) =>
    items.map((item) => [...item.querySelectorAll('td')].map((td) => td.textContent.trim()))
  );
  return rows.map((cells) => ({ name: cells[0], time: parseUtc(cells[1]), value: cells[2] }));
}

async function openOverview(page) {
  // The default address opens the mission overview: this checks that too.
  await page.goto(new URL('/', args.url).href, { waitUntil: 'load' });
  const title = await waitFor(
    () => page.$eval('.l-browse-bar__object-name', (e) => e.textContent.trim()),
    (t) => t === 'Mission overview'
  );
  record('the page opens the RSE mission overview', title === 'Mission overview', `browse bar shows "${title?.error ?? title}"`);
  const packets = await waitFor(
    () => page.evaluate(async () => (await window.openmct.rse.ready).dictionary.packetNames()),
    (p) => Array.isArray(p) && p.length > 0
  );
  record('the display dictionary is loaded', Array.isArray(packets) && packets.length > 0,
    Array.isArray(packets) ? `${packets.length} packets: ${packets.join(' ')}` : JSON.stringify(packets));
  return Array.isArray(packets) ? packets : [];
}

async function checkPlots(page) {
  const plotFrames = [];
  for (const f of await frames(page)) {
    if (await f.handle.$('.gl-plot-chart-area')) plotFrames.push(f);
  }
  record('the overview has plots', plotFrames.length > 0, plotFrames.map((f) => f.name).join(', '));
  for (const { name, handle } of plotFrames) {
    const first = await waitFor(
      () => hoveredLegend(page, handle),
      (rows) => Array.isArray(rows) && rows.length > 0 && rows.every((r) => r.time !== undefined)
    );
    const drawn = Array.isArray(first) && first.length > 0 && first.every((r) => r.time !== undefined);
    if (!drawn) {
      record(`plot "${name}" draws points`, false, `legend: ${JSON.stringify(first)}`);
      continue;
    }
    // The rover sends these packets at 1 Hz: a few seconds bring newer points.
    const later = await waitFor(
      () => hoveredLegend(page, handle),
      (rows) => Array.isArray(rows) && rows.length === first.length && rows.every((r, i) => r.time > first[i].time),
      15000,
      1500
    );
    const advanced = Array.isArray(later) && later.length === first.length && later.every((r, i) => r.time > first[i].time);
    record(
      `plot "${name}" receives live points`,
      advanced,
      (Array.isArray(later) ? later : first)
        .map((r, i) => `${r.name} ${iso(first[i].time).slice(11, 23)} -> ${r.time ? iso(r.time).slice(11, 23) : '?'} (${r.value})`)
        .join('; ')
    );
  }
}

async function checkSubscription(page, packets) {
  const wanted = ['ROVER_STATE', 'DRIVES'].filter((p) => packets.includes(p));
  const counts = await page.evaluate(async (names) => {
    const counts = {};
    const stops = [];
    for (const name of names) {
      counts[name] = 0;
      const object = await window.openmct.objects.get(`rse:packet.${name}`);
      stops.push(window.openmct.telemetry.subscribe(object, () => (counts[name] += 1)));
    }
    await new Promise((resolve) => setTimeout(resolve, 4500));
    stops.forEach((stop) => stop());
    return counts;
  }, wanted);
  const ok = wanted.length > 0 && wanted.every((p) => counts[p] >= 2);
  record('realtime datums reach an openmct.telemetry.subscribe in the page', ok, `in 4.5 s: ${JSON.stringify(counts)}`);
}

async function checkEventLog(page, packets) {
  if (!packets.includes('EVENT')) {
    record('the event log shows rows', false, 'no EVENT packet in the dictionary');
    return;
  }
  const frame = await frameNamed(page, 'Event log');
  const rows = await waitFor(
    () => frame.$$eval('.c-telemetry-table__body tr', (trs) => trs.map((tr) => tr.textContent.replace(/\s+/g, ' ').trim())),
    (r) => Array.isArray(r) && r.length > 0
  );
  const ok = Array.isArray(rows) && rows.length > 0;
  record('the event log shows rows', ok, ok ? `${rows.length} rows, newest: "${rows[0].slice(0, 100)}"` : JSON.stringify(rows));
}

// Points of an SVG polyline and the size of its box.
function polylineProbe(selector) {
  return (sel) => {
    const e = document.querySelector(sel);
    if (!e) return { found: false };
    const points = (e.getAttribute('points') || '').trim().split(/\s+/).filter(Boolean).length;
    const box = e.getBBox();
    return { found: true, points, width: box.width, height: box.height };
  };
}

async function checkMap(page, { expectRocks = true } = {}) {
  const geometry = (g) => g.found && g.points >= 2 && g.width + g.height > 0;
  for (const [label, selector] of [['plan', '#rse-map-plan.rse-map-plan'], ['track', '#rse-map-track.rse-map-track']]) {
    const g = await waitFor(() => page.evaluate(polylineProbe(selector), selector), geometry);
    record(`the map draws the ${label} (${selector})`, geometry(g),
      g.found ? `${g.points} points, box ${g.width?.toFixed(2)} x ${g.height?.toFixed(2)} m` : `not found ${JSON.stringify(g)}`);
  }
  if (expectRocks) {
    const rocks = await waitFor(
      () => page.evaluate(async () => {
        const map = await (await fetch('/api/map')).json();
        return { expected: (map.rocks || []).length, drawn: document.querySelectorAll('.rse-map-rock').length };
      }),
      (r) => r.expected !== undefined && r.drawn === r.expected
    );
    record('the map draws every rock of /api/map', rocks.drawn === rocks.expected, `${rocks.drawn} of ${rocks.expected}`);
  }
}

async function checkDriveHealth(page) {
  const wheels = await waitFor(
    () => page.$$eval('#rse-drive-health tr.rse-wheel', (rows) =>
      rows.map((r) => ({ wheel: r.dataset.wheel, state: r.cells[1].textContent.trim(), current: r.cells[4].textContent.trim() }))
    ),
    (w) => Array.isArray(w) && w.length === 6 && w.every((x) => x.state !== '—')
  );
  const ok = Array.isArray(wheels) && wheels.length === 6 && wheels.every((x) => x.state !== '—');
  record('the drive-health panel shows 6 wheels with data', ok,
    Array.isArray(wheels) ? wheels.map((w) => `${w.wheel} ${w.state} ${w.current} A`).join('; ') : JSON.stringify(wheels));
}

async function checkMissionState(page) {
  const mode = await waitFor(
    () => page.$eval('#rse-mission-state [data-tile="mode"] .rse-tile__value', (e) => e.textContent.trim()),
    (m) => typeof m === 'string' && m !== '—' && m !== ''
  );
  record('the mission-state panel shows the mode', typeof mode === 'string' && mode !== '—' && mode !== '', `mode "${mode?.error ?? mode}"`);
}

async function checkHistory(page, packets) {
  const { start, end } = args.interval;
  for (const name of args.historyPackets) {
    if (!packets.includes(name)) {
      record(`history of ${name} comes back`, false, 'not in the dictionary');
      continue;
    }
    const r = await page.evaluate(async (packet, s, e) => {
      const object = await window.openmct.objects.get(`rse:packet.${packet}`);
      const datums = await window.openmct.telemetry.request(object, { start: s, end: e });
      const times = datums.map((d) => d.utc);
      const keys = (await window.openmct.rse.ready).dictionary.packet(packet).fields.map((f) => f.key);
      return {
        count: datums.length,
        inside: times.every((t) => t >= s && t <= e),
        ordered: times.every((t, i) => i === 0 || t >= times[i - 1]),
        first: times[0],
        last: times[times.length - 1],
        missingFields: datums.length ? keys.filter((k) => !(k in datums[0])).slice(0, 5) : []
      };
    }, name, start, end);
    const ok = r.count >= args.minPoints && r.inside && r.ordered && r.missingFields.length === 0;
    record(`history of ${name} over ${iso(start)} .. ${iso(end)} comes back`, ok,
      `${r.count} datums${r.count ? ` ${iso(r.first).slice(11, 19)}..${iso(r.last).slice(11, 19)}` : ''}, ` +
        `inside ${r.inside}, oldest first ${r.ordered}${r.missingFields.length ? `, missing fields ${r.missingFields}` : ''}`);
  }
  // What the operator sees of the same interval: the conductor fixed on it.
  await page.evaluate((s, e) => window.openmct.time.setMode('fixed', { start: s, end: e }), start, end);
  await sleep(1000);
  const track = await waitFor(
    () => page.evaluate(polylineProbe('#rse-map-track'), '#rse-map-track'),
    (g) => g.found && g.points >= 2
  );
  record('with the conductor on the interval the map draws the archived track', track.found && track.points >= 2,
    `${track.points ?? 0} points`);
  const frame = await frameNamed(page, 'Position x, y');
  if (!frame) {
    record('with the conductor on the interval the position plot shows archived points', false, 'no "Position x, y" plot');
    return;
  }
  const legend = await waitFor(
    () => hoveredLegend(page, frame),
    (rows) => Array.isArray(rows) && rows.length > 0 && rows.every((r) => r.time >= start && r.time <= end)
  );
  const ok = Array.isArray(legend) && legend.length > 0 && legend.every((r) => r.time >= start && r.time <= end);
  record('with the conductor on the interval the position plot shows archived points', ok,
    Array.isArray(legend) ? legend.map((r) => `${r.name} ${r.time ? iso(r.time) : '?'} ${r.value}`).join('; ') : JSON.stringify(legend));
}

const browser = await puppeteer.launch({
  executablePath: args.chromium,
  // Root in a container: Chromium's sandbox cannot start.
  args: ['--no-sandbox', '--disable-dev-shm-usage'],
  defaultViewport: { width: 1920, height: 1080 }
});
const pageErrors = [];
try {
  const page = await browser.newPage();
  page.on('pageerror', (error) => pageErrors.push(error.message));
  const packets = await openOverview(page);
  if (packets.length > 0) {
    if (args.live) {
      await checkPlots(page);
      await checkSubscription(page, packets);
      await checkEventLog(page, packets);
      await checkMap(page);
      await checkDriveHealth(page);
      await checkMissionState(page);
    }
    if (args.history) {
      await checkHistory(page, packets);
    }
  }
  record('no uncaught exception in the page', pageErrors.length === 0, pageErrors.slice(0, 3).join(' | '));
  fs.mkdirSync(path.dirname(path.resolve(args.screenshot)), { recursive: true });
  await page.screenshot({ path: args.screenshot });
  console.log(`screenshot: ${args.screenshot}`);
} catch (error) {
  record('the test ran to its end', false, error.stack || String(error));
} finally {
  await browser.close();
}

const passed = results.filter((r) => r.ok).length;
const failed = results.length - passed;
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed > 0 ? 1 : 0);

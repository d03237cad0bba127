#!/usr/bin/env node
// MOCK of rse-ground serve, for developing the browser side only.
//
// It speaks the HTTP and WebSocket contract of docs/mission_control.md with
// MADE-UP telemetry: a rover driving a fixed path across the demo site, plus
// invented POWER and HAZARDS packets and invented display limits. It decodes
// nothing and knows no link; no test uses it (the browser test runs against
// the real server). Its dictionary is docs/dictionary.json with the array
// fields expanded as the contract says.
//
//   node ground/mission_control/web/dev/mock_server.mjs [--port 8091] [--archive FILE]
//        [--omit POWER,HAZARDS] [--no-live] [--backfill SECONDS]
//
// --archive FILE keeps every datum (JSON lines) across restarts, so the
// history mode of the browser test can be tried: run, stop, restart with
// --no-live, ask for the past interval. --backfill S makes S seconds of past
// telemetry at start. --omit leaves packets out of the dictionary (to see the
// views degrade).

import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { WebSocketServer } from 'ws';

const here = path.dirname(fileURLToPath(import.meta.url));
const webDir = path.resolve(here, '..');
const repoDir = path.resolve(webDir, '../../..');

function parseArgs(argv) {
  const args = { port: 8091, host: '127.0.0.1', archive: undefined, omit: [], live: true, backfill: 0 };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--port') args.port = Number(argv[++i]);
    else if (a === '--host') args.host = argv[++i];
    else if (a === '--archive') args.archive = argv[++i];
    else if (a === '--omit') args.omit = argv[++i].split(',').filter(Boolean);
    else if (a === '--no-live') args.live = false;
    else if (a === '--backfill') args.backfill = Number(argv[++i]);
    else {
      console.error(`mock_server: unknown argument ${a}`);
      process.exit(2);
    }
  }
  return args;
}
const args = parseArgs(process.argv.slice(2));

// ---------------------------------------------------------------- dictionary
const flight = JSON.parse(fs.readFileSync(path.join(repoDir, 'docs/dictionary.json'), 'utf8'));
// Invented packets: stand-ins until the flight dictionary has its own.
const inventedPackets = [
  {
    name: 'POWER',
    apid: 0x18,
    description: 'MOCK: battery and motor temperatures (invented by the mock)',
    fields: [
      { name: 'battery_voltage', type: 'f32', count: 1, units: 'V', description: 'MOCK battery voltage' },
      { name: 'state_of_charge', type: 'f32', count: 1, units: '%', description: 'MOCK state of charge' },
      { name: 'bus_current', type: 'f32', count: 1, units: 'A', description: 'MOCK bus current' },
      { name: 'motor_temperature', type: 'f32', count: 6, units: 'degC', description: 'MOCK per wheel (FL ML RL FR MR RR)' }
    ]
  },
  {
    name: 'HAZARDS',
    apid: 0x19,
    description: 'MOCK: hazards seen (invented by the mock)',
    fields: [
      { name: 'count', type: 'u8', count: 1, units: '', description: 'MOCK hazards listed' },
      { name: 'x', type: 'f32', count: 8, units: 'm', description: 'MOCK hazard x' },
      { name: 'y', type: 'f32', count: 8, units: 'm', description: 'MOCK hazard y' },
      { name: 'radius', type: 'f32', count: 8, units: 'm', description: 'MOCK hazard radius' }
    ]
  }
];
// Invented limits, to see the colouring.
const inventedLimits = {
  'DRIVES.current': { warn_low: -2.4, warn_high: 2.4, alarm_low: -2.8, alarm_high: 2.8 },
  'ROVER_STATE.position_sigma': { warn_high: 0.5, alarm_high: 1.0 },
  'POWER.battery_voltage': { warn_low: 25, alarm_low: 23 },
  'POWER.state_of_charge': { warn_low: 30, alarm_low: 15 },
  'POWER.motor_temperature': { warn_high: 60, alarm_high: 80 }
};

function expand(packet) {
  const fields = [];
  for (const f of packet.fields) {
    const base = { type: f.type, units: f.units || '', description: f.description || '' };
    const limits = inventedLimits[`${packet.name}.${f.name}`];
    if (f.type === 'chr' || f.type === 'blob' || f.count === 1) {
      fields.push({ key: f.name, name: f.name, ...base, ...(limits ? { limits } : {}) });
    } else {
      for (let i = 0; i < f.count; i++) {
        fields.push({ key: `${f.name}.${i}`, name: `${f.name}.${i}`, ...base, ...(limits ? { limits } : {}) });
      }
    }
  }
  return { name: packet.name, apid: packet.apid, description: packet.description, fields };
}

const dictionary = {
  name: 'RSE rover',
  packets: [...flight.telemetry, ...inventedPackets].filter((p) => !args.omit.includes(p.name)).map(expand)
};
const packetByName = new Map(dictionary.packets.map((p) => [p.name, p]));

// ---------------------------------------------------------------- archive
const archive = new Map(); // packet -> datums, oldest first
let archiveStream;
if (args.archive) {
  if (fs.existsSync(args.archive)) {
    for (const line of fs.readFileSync(args.archive, 'utf8').split('\n')) {
      if (!line) continue;
      const { packet, datum } = JSON.parse(line);
      if (!archive.has(packet)) archive.set(packet, []);
      archive.get(packet).push(datum);
    }
  }
  archiveStream = fs.createWriteStream(args.archive, { flags: 'a' });
}
let packetsReceived = 0;
const clients = new Set();

function publish(packet, datum) {
  if (!packetByName.has(packet)) return;
  packetsReceived += 1;
  if (!archive.has(packet)) archive.set(packet, []);
  archive.get(packet).push(datum);
  archiveStream?.write(`${JSON.stringify({ packet, datum })}\n`);
  const text = JSON.stringify({ packet, datum });
  for (const client of clients) {
    if (client.subscriptions.has(packet) && client.readyState === client.OPEN) client.send(text);
  }
}

// ---------------------------------------------------------------- made-up rover
// Every field starts at 0 (or ""), then the simulation sets what the views use.
function blank(packetName, utc, met) {
  const datum = { utc, met };
  for (const f of packetByName.get(packetName)?.fields || []) datum[f.key] = f.type === 'chr' ? '' : 0;
  return datum;
}

const PATH = [
  [0, 0],
  [4, 0.4],
  [7.8, 0.6],
  [12.5, -0.6],
  [16, 0.2],
  [20, 0.4],
  [24, 0]
];
const SPEED = 0.3; // m/s
const TASKS = ['tables', 'can_io', 'estimator', 'drive_modes', 'health', 'fault_prot', 'commands', 'habitual', 'deliberative', 'plan_exec', 'telemetry'];
const EVENTS = [
  [1, 101, 'plan made: 6 legs, risk used 4.1e-3'],
  [1, 410, 'leg complete'],
  [0, 900, 'debug: follower lookahead 0.8 m'],
  [2, 724, 'drive over-current MR'],
  [1, 725, 'drive over-current cleared MR'],
  [3, 730, 'pose uncertain: sigma 0.62 m'],
  [4, 726, 'battery low (mock)']
];

function pathLength() {
  let s = 0;
  for (let i = 1; i < PATH.length; i++) s += Math.hypot(PATH[i][0] - PATH[i - 1][0], PATH[i][1] - PATH[i - 1][1]);
  return s;
}
const TOTAL = pathLength();

// Out along PATH, 10 m worth of rest at the goal, back along it, and so on.
function pathFor(lap) {
  return lap % 2 === 0 ? PATH : [...PATH].reverse();
}

function poseAt(distance) {
  const path = pathFor(Math.floor(distance / (TOTAL + 10)));
  let d = distance % (TOTAL + 10);
  for (let i = 1; i < path.length; i++) {
    const [x0, y0] = path[i - 1];
    const [x1, y1] = path[i];
    const seg = Math.hypot(x1 - x0, y1 - y0);
    if (d <= seg) {
      return { x: x0 + ((x1 - x0) * d) / seg, y: y0 + ((y1 - y0) * d) / seg, heading: Math.atan2(y1 - y0, x1 - x0), moving: true };
    }
    d -= seg;
  }
  const [xa, ya] = path[path.length - 2];
  const [xb, yb] = path[path.length - 1];
  return { x: xb, y: yb, heading: Math.atan2(yb - ya, xb - xa), moving: false };
}

const start = Date.now();
let planNumber = 0;
let eventSequence = 0;
let lastLap = -1;

// A new plan each lap of the mock's route: its PLAN_PATH.
function publishPlanPath(lap, utc, met) {
  const path = pathFor(lap);
  planNumber += 1;
  const p = blank('PLAN_PATH', utc, met);
  Object.assign(p, {
    plan_number: planNumber,
    plan_time: met,
    status: 0,
    steps: PATH.length - 1,
    risk_bound: 1e-2,
    risk_used: 4.1e-3,
    length: TOTAL,
    process_sigma: 0.05,
    'start_cov.0': 0.01,
    'start_cov.1': 0.002,
    'start_cov.2': 0.002,
    'start_cov.3': 0.006,
    goal_x: path[path.length - 1][0],
    goal_y: path[path.length - 1][1]
  });
  path.forEach(([x, y], i) => {
    p[`mean_x.${i}`] = x;
    p[`mean_y.${i}`] = y;
  });
  publish('PLAN_PATH', p);
}

// HK and the state estimate.
function publishRoverState(t, pose, sigma, utc, met) {
  const hk = blank('HK', utc, met);
  Object.assign(hk, { utc_at_met_zero: (utc - met * 1000) / 1000, mode: pose.moving ? 2 : 1, task_count: TASKS.length, frames_run: met * 100 });
  publish('HK', hk);

  const rs = blank('ROVER_STATE', utc, met);
  Object.assign(rs, {
    estimate_valid: 1,
    yaw_from_imu: 1,
    x: pose.x + 0.03 * Math.sin(t / 3),
    y: pose.y + 0.03 * Math.cos(t / 4),
    heading: pose.heading,
    position_sigma: sigma,
    speed: pose.moving ? SPEED : 0,
    'covariance.0': sigma * sigma,
    'covariance.4': sigma * sigma,
    fixes_accepted: Math.max(0, Math.floor(t / 2))
  });
  publish('ROVER_STATE', rs);
}

// The drives, their health and fault protection: the MR drive's current spikes
// now and then, and the estimator and fault protection answer it.
function publishDrivesAndHealth(t, pose, utc, met) {
  const mrSpike = t % 40 >= 30 && t % 40 < 34;
  const drives = blank('DRIVES', utc, met);
  for (let w = 0; w < 6; w++) {
    const spike = w === 4 && mrSpike;
    drives[`state.${w}`] = 4;
    drives[`commanded.${w}`] = pose.moving ? 2.0 : 0;
    drives[`speed.${w}`] = pose.moving ? 1.95 + 0.05 * Math.sin(t + w) : 0;
    drives[`current.${w}`] = spike ? 2.9 : pose.moving ? 1.1 + 0.3 * Math.sin(t / 5 + w) + 0.1 * w : 0.05;
    if (spike) drives[`last_emcy.${w}`] = 0x2310;
  }
  publish('DRIVES', drives);

  const health = blank('HEALTH', utc, met);
  health.active_faults = mrSpike ? 2 ** (11 + 4) : 0;
  for (let w = 0; w < 6; w++) {
    health[`drive_mode.${w}`] = w === 4 && mrSpike ? 1 : 0;
    health[`p_nominal.${w}`] = w === 4 && mrSpike ? 0.35 : 0.98;
    health[`p_degraded.${w}`] = w === 4 && mrSpike ? 0.6 : 0.01;
    health[`power_factor.${w}`] = 1;
  }
  publish('HEALTH', health);

  const fp = blank('FAULT_PROTECTION', utc, met);
  if (mrSpike) Object.assign(fp, { hold_reasons: 1, response_count: 1, 'fault_id.0': 5, 'fault_class.0': 2, 'state.0': 1 });
  publish('FAULT_PROTECTION', fp);
}

// The plan executive, and PLAN every fifth second.
function publishPlans(t, pose, distance, utc, met) {
  const exec = blank('PLAN_EXEC', utc, met);
  Object.assign(exec, { state: 2, plan_name: 'traverse_demo', activity_count: 6, running: 1, completed: Math.floor(distance / 5) % 6, selection_status: 1 });
  publish('PLAN_EXEC', exec);
  if (t % 5 !== 0) return;
  const plan = blank('PLAN', utc, met);
  const legIndex = Math.min(PATH.length - 2, Math.floor(((distance % (TOTAL + 10)) / TOTAL) * (PATH.length - 1)));
  Object.assign(plan, {
    status: pose.moving ? 3 : 5,
    plan_status: 0,
    goal_count: 2,
    goal_index: 0,
    leg_count: PATH.length - 1,
    leg_index: legIndex,
    waypoint_count: 1,
    risk_bound: 1e-2,
    risk_in_force: 1e-2,
    risk_used: 4.1e-3,
    plan_length: TOTAL,
    current_leg_id: 100 + legIndex,
    'goal_x.0': 24,
    'goal_y.0': 0,
    'goal_x.1': 20,
    'goal_y.1': -6,
    'priority.1': 5
  });
  publish('PLAN', plan);
}

// POWER and the hazards seen near the rover.
function publishPowerAndHazards(t, pose, utc, met) {
  const power = blank('POWER', utc, met);
  Object.assign(power, { battery_voltage: 28.5 - 0.01 * Math.max(0, t) % 6, state_of_charge: Math.max(5, 95 - 0.02 * Math.max(0, t)), bus_current: pose.moving ? 6.5 : 0.8 });
  for (let w = 0; w < 6; w++) power[`motor_temperature.${w}`] = 35 + 5 * w + 3 * Math.sin(t / 30 + w);
  publish('POWER', power);

  const hazards = blank('HAZARDS', utc, met);
  const seen = [[13.5, 1.3, 0.45], [18.5, -1.6, 0.35]].filter(([x]) => Math.abs(x - pose.x) < 8);
  hazards.count = seen.length;
  seen.forEach(([x, y, r], i) => Object.assign(hazards, { [`x.${i}`]: x, [`y.${i}`]: y, [`radius.${i}`]: r }));
  publish('HAZARDS', hazards);
}

// TASK_TIMING of every task, and an event every third second.
function publishTimingAndEvents(t, utc, met) {
  TASKS.forEach((name, index) => {
    const tt = blank('TASK_TIMING', utc + 100 + index * 10, met + 0.1 + index * 0.01);
    const mean = 40 + 25 * index + 15 * Math.sin(t / 7 + index);
    Object.assign(tt, { task_index: index, task_name: name, runs: Math.max(0, t) * 100, mean_us: Math.round(mean), cpu_mean_us: Math.round(mean * 1.1), max_us: Math.round(mean * 2), cpu_timed: 1 });
    publish('TASK_TIMING', tt);
  });
  if (t % 3 !== 0) return;
  const [severity, id, text] = EVENTS[Math.abs(t / 3) % EVENTS.length];
  const e = blank('EVENT', utc + 500, met + 0.5);
  Object.assign(e, { event_sequence: ++eventSequence, event_time: met + 0.5, event_id: id, severity, text });
  publish('EVENT', e);
}

// The packets of one simulated second t (seconds since the mock's start; may be negative for backfill).
function second(t, utcBase) {
  const met = 1000 + t;
  const utc = utcBase;
  const distance = Math.max(0, t) * SPEED;
  const lap = Math.floor(distance / (TOTAL + 10));
  const pose = poseAt(distance);
  const sigma = 0.08 + 0.05 * Math.abs(Math.sin(t / 17));
  if (lap !== lastLap) {
    lastLap = lap;
    publishPlanPath(lap, utc, met);
  }
  publishRoverState(t, pose, sigma, utc, met);
  publishDrivesAndHealth(t, pose, utc, met);
  publishPlans(t, pose, distance, utc, met);
  publishPowerAndHazards(t, pose, utc, met);
  publishTimingAndEvents(t, utc, met);
}

for (let s = -args.backfill; s < 0; s++) second(s, start + s * 1000);
if (args.live) {
  let t = 0;
  second(t, Date.now());
  setInterval(() => second(++t, Date.now()), 1000);
}

// ---------------------------------------------------------------- HTTP
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.css': 'text/css', '.json': 'application/json', '.png': 'image/png', '.svg': 'image/svg+xml', '.woff': 'font/woff', '.woff2': 'font/woff2', '.ttf': 'font/ttf', '.map': 'application/json' };

function sendJson(res, status, body) {
  res.writeHead(status, { 'Content-Type': 'application/json', 'Cache-Control': 'no-store' });
  res.end(JSON.stringify(body));
}

function sendFile(res, file) {
  fs.readFile(file, (error, data) => {
    if (error) {
      res.writeHead(404);
      res.end('not found');
      return;
    }
    res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] || 'application/octet-stream' });
    res.end(data);
  });
}

const COARSE_MAP = {
  site: { x_min: -5, x_max: 30, y_min: -10, y_max: 10 },
  rocks: [
    { id: 0, points: [[5, 1.8], [6.5, 1.8], [6.5, 3.2], [5, 3.2]] },
    { id: 1, points: [[9, -3.5], [11, -3.2], [10.2, -1.6]] },
    { id: 2, points: [[16, 1.6], [17.5, 1.6], [17.5, 3], [16, 3]] },
    { id: 3, points: [[14, -5], [15.5, -5.5], [16, -4], [14.5, -3.5]] }
  ]
};

const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://mock');
  const p = decodeURIComponent(url.pathname);
  if (p.split('/').includes('..')) return sendJson(res, 400, { error: 'bad path' });
  if (p === '/api/dictionary') return sendJson(res, 200, dictionary);
  if (p === '/api/map') return sendJson(res, 200, COARSE_MAP);
  if (p === '/api/status') {
    return sendJson(res, 200, { packets_received: packetsReceived, packets_archived: packetsReceived, decode_errors: 0, clients: clients.size, archive: args.archive || '(memory)', link: 'MOCK (no link)' });
  }
  if (p === '/api/history') {
    const packet = url.searchParams.get('packet');
    const from = Number(url.searchParams.get('start'));
    const to = Number(url.searchParams.get('end'));
    if (!packetByName.has(packet) || !Number.isFinite(from) || !Number.isFinite(to)) return sendJson(res, 400, { error: 'packet, start, end' });
    const datums = (archive.get(packet) || []).filter((d) => d.utc >= from && d.utc <= to).sort((a, b) => a.utc - b.utc);
    return sendJson(res, 200, datums.slice(0, 20000));
  }
  if (p.startsWith('/openmct/')) return sendFile(res, path.join(webDir, 'node_modules/openmct/dist', p.slice('/openmct/'.length)));
  return sendFile(res, path.join(webDir, p === '/' ? 'index.html' : p));
});

const wss = new WebSocketServer({ server, path: '/realtime' });
wss.on('connection', (socket) => {
  socket.subscriptions = new Set();
  clients.add(socket);
  socket.on('message', (data) => {
    try {
      const m = JSON.parse(String(data));
      if (typeof m.subscribe === 'string') socket.subscriptions.add(m.subscribe);
      if (typeof m.unsubscribe === 'string') socket.subscriptions.delete(m.unsubscribe);
    } catch {
      // ignored, as the real server may
    }
  });
  socket.on('close', () => clients.delete(socket));
});

server.listen(args.port, args.host, () => {
  console.log(`MOCK rse-ground serve on http://${args.host}:${args.port}/ (made-up telemetry${args.live ? '' : ', no live data'})`);
});
for (const signal of ['SIGINT', 'SIGTERM']) {
  process.on(signal, () => {
    archiveStream?.end();
    process.exit(0);
  });
}

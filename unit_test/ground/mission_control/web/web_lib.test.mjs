// The mission control display's JavaScript library (ground/mission_control/web/lib)
// under Node's test runner: what the browser side computes from the display
// dictionary and the server's answers, without a browser or a server.
//   node --test unit_test/ground/mission_control/web/web_lib.test.mjs   (make mission-control-web-test)

import assert from 'node:assert/strict';
import fs from 'node:fs';
import { test } from 'node:test';

import { DisplayDictionary, splitArrayKey } from '../../../../ground/mission_control/web/lib/dictionary.js';
import { enumerationsFor, nameOf, NAMES } from '../../../../ground/mission_control/web/lib/enumerations.js';
import { requestHistory } from '../../../../ground/mission_control/web/lib/history.js';
import { fieldLimits, limitState, makeLimitDefinition, makeLimitEvaluator } from '../../../../ground/mission_control/web/lib/limits.js';
import { formatNumber } from '../../../../ground/mission_control/web/lib/number-format.js';
import { planFromDatum, riskEllipses, upperQuantile } from '../../../../ground/mission_control/web/lib/risk-ellipses.js';
import { id, RseObjects } from '../../../../ground/mission_control/web/lib/rse-objects.js';
import { hazardFields, powerFields } from '../../../../ground/mission_control/web/lib/special-fields.js';
import { TaskDirectory } from '../../../../ground/mission_control/web/lib/task-directory.js';
import { packetMetadata, fieldMetadata } from '../../../../ground/mission_control/web/lib/telemetry-metadata.js';

const f = (key, extra = {}) => ({ key, name: key, type: 'f32', units: '', ...extra });
const array = (base, n, extra = {}) => Array.from({ length: n }, (_, i) => f(`${base}.${i}`, extra));

function dictionary({ power = true, hazards = true } = {}) {
  const packets = [
    { name: 'HK', fields: [f('mode', { type: 'u8' }), f('estop', { type: 'u8' })] },
    { name: 'EVENT', fields: [f('event_id', { type: 'u16' }), f('severity', { type: 'u8' }), f('text', { type: 'chr' })] },
    { name: 'TASK_TIMING', fields: [f('task_index', { type: 'u8' }), f('task_name', { type: 'chr' }), f('mean_us', { type: 'u32' }), f('cpu_mean_us', { type: 'u32' })] },
    { name: 'ROVER_STATE', fields: [f('x', { units: 'm' }), f('y', { units: 'm' }), f('heading'), f('position_sigma', { limits: { warn_high: 0.5, alarm_high: 1 } }), f('speed')] },
    { name: 'DRIVES', fields: [...array('state', 6, { type: 'u8' }), ...array('current', 6, { units: 'A', limits: { warn_high: 2.4, alarm_high: 2.8, warn_low: -2.4, alarm_low: -2.8 } })] }
  ];
  if (power) {
    packets.push({ name: 'POWER', fields: [f('battery_voltage', { units: 'V' }), f('state_of_charge', { units: '%' }), ...array('motor_temperature', 6)] });
  }
  if (hazards) {
    packets.push({ name: 'HAZARDS', fields: [f('hazard_count', { type: 'u8' }), ...array('x', 4), ...array('y', 4), ...array('radius', 4)] });
  }
  return new DisplayDictionary({ name: 'RSE rover', packets });
}

test('array keys split into base and index, and come back in index order', () => {
  assert.deepEqual(splitArrayKey('current.10'), { base: 'current', index: 10 });
  assert.deepEqual(splitArrayKey('x'), { base: 'x', index: -1 });
  const d = new DisplayDictionary({ packets: [{ name: 'P', fields: [f('v.10'), f('v.2'), f('v.0'), f('v.1'), ...array('v', 10).slice(3)] }] });
  assert.deepEqual(d.arrayKeys('P', 'v').slice(0, 3), ['v.0', 'v.1', 'v.2']);
  assert.equal(d.arrayKeys('P', 'v')[10], 'v.10');
  assert.deepEqual(d.arrays('P'), [{ base: 'v', count: 11 }]);
  assert.throws(() => new DisplayDictionary({}), /packets/);
});

test('a value on a limit is within it; beyond a warning limit a warning, beyond an alarm limit an alarm', () => {
  const limits = { warn_low: -1, warn_high: 1, alarm_low: -2, alarm_high: 2 };
  assert.equal(limitState(1, limits), undefined);
  assert.equal(limitState(-2, limits)?.level, 'warning');
  assert.deepEqual(limitState(1.5, limits), { level: 'warning', side: 'high' });
  assert.deepEqual(limitState(-2.5, limits), { level: 'alarm', side: 'low' });
  assert.equal(limitState('3', limits)?.level, 'alarm');
  assert.equal(limitState(NaN, limits), undefined);
  assert.equal(limitState(5, undefined), undefined);
  assert.deepEqual(limitState(0.6, { warn_high: 0.5 }), { level: 'warning', side: 'high' });
});

test('the limit evaluator colours a value, and a row by its worst value, with Open MCT classes', () => {
  const evaluator = makeLimitEvaluator(new Map([['a', { warn_high: 1, alarm_high: 2 }], ['b', { warn_high: 1 }]]));
  assert.equal(evaluator.evaluate({ a: 2.5 }, { key: 'a', source: 'a' }).cssClass, 'is-limit--upr is-limit--red');
  assert.equal(evaluator.evaluate({ a: 1.5 }, { key: 'a' }).name, 'Warning High');
  assert.equal(evaluator.evaluate({ a: 0.5, b: 9 }, { key: 'a' }), undefined);
  assert.equal(evaluator.evaluate({ a: 3, b: 9 }).cssClass, 'is-limit--upr is-limit--red');
  assert.equal(evaluator.evaluate({ a: 0, b: 9 }).cssClass, 'is-limit--upr is-limit--yellow');
  assert.equal(evaluator.evaluate({ a: 0, b: 0 }), undefined);
});

test('limit lines hold each level of each value that has one', async () => {
  const levels = await makeLimitDefinition(new Map([['a', { warn_low: -1, alarm_high: 2 }]])).limits();
  assert.deepEqual(levels, { WARNING: { low: { color: 'yellow', a: -1 } }, CRITICAL: { high: { color: 'red', a: 2 } } });
  assert.equal(await makeLimitDefinition(new Map()).limits(), undefined);
});

test('event severity WARN is a warning and ERROR an alarm unless the dictionary gives limits', () => {
  const limits = fieldLimits('EVENT', { key: 'severity' });
  assert.equal(limitState(1, limits), undefined);
  assert.equal(limitState(2, limits).level, 'warning');
  assert.equal(limitState(3, limits).level, 'alarm');
  assert.deepEqual(fieldLimits('EVENT', { key: 'severity', limits: { alarm_high: 3 } }), { alarm_high: 3 });
});

test('the risk ellipses are the planner quantile times the covariance axes, turned as the covariance', () => {
  assert.ok(Math.abs(upperQuantile(1e-2) - 2.3263478740408408) < 1e-8);
  assert.ok(Math.abs(upperQuantile(1e-6) - 4.753424308822899) < 1e-8);
  const datum = {
    plan_number: 3, steps: 2, risk_bound: 1e-2, risk_used: 1e-3, process_sigma: 0.1,
    'start_cov.0': 0.04, 'start_cov.1': 0, 'start_cov.2': 0, 'start_cov.3': 0.01,
    'mean_x.0': 0, 'mean_y.0': 0, 'mean_x.1': 1, 'mean_y.1': 0, 'mean_x.2': 2, 'mean_y.2': 1, goal_x: 2, goal_y: 1
  };
  const plan = planFromDatum(datum);
  assert.equal(plan.means.length, 3);
  assert.deepEqual(plan.goal, { x: 2, y: 1 });
  const [e0, e1] = riskEllipses(plan);
  const k = upperQuantile(1e-2);
  assert.ok(Math.abs(e0.rx - k * 0.2) < 1e-12 && Math.abs(e0.ry - k * 0.1) < 1e-12 && e0.angleDeg === 0);
  // t = 1: Sigma_0 + 0.01 I
  assert.ok(Math.abs(e1.rx - k * Math.sqrt(0.05)) < 1e-12 && Math.abs(e1.ry - k * Math.sqrt(0.02)) < 1e-12);
  // Equal variances with a covariance: the major axis at 45 degrees.
  const tilted = riskEllipses({ ...plan, startCov: [0.02, 0.01, 0.01, 0.02], processSigma: 0 })[0];
  assert.ok(Math.abs(tilted.angleDeg - 45) < 1e-9);
  assert.equal(planFromDatum({ steps: 0 }), undefined);
  assert.deepEqual(riskEllipses({ ...plan, riskBound: 0.7 }), []);
});

test('history pages through truncated answers without losing or repeating a datum', async () => {
  const all = Array.from({ length: 25 }, (_, i) => ({ utc: 1000 + Math.floor(i / 2), i }));
  const asked = [];
  globalThis.fetch = async (url) => {
    const q = new URL(url, 'http://x').searchParams;
    asked.push(q.get('start'));
    const inside = all.filter((d) => d.utc >= Number(q.get('start')) && d.utc <= Number(q.get('end')));
    const page = inside.slice(0, 6);
    const body = inside.length > 6 ? { datums: page, truncated: true } : page;
    return { ok: true, json: async () => body };
  };
  const got = await requestHistory('ROVER_STATE', 0, 5000);
  assert.deepEqual(got.map((d) => d.i), all.map((d) => d.i));
  assert.ok(asked.length > 1);
  globalThis.fetch = async () => ({ ok: false, status: 500 });
  await assert.rejects(requestHistory('X', 0, 1), /HTTP 500/);
});

test('POWER and HAZARDS fields are found by name and units, and missing packets are reported absent', () => {
  const d = dictionary();
  assert.deepEqual(powerFields(d), {
    present: true,
    voltage: 'battery_voltage',
    stateOfCharge: 'state_of_charge',
    motorTemperatures: ['motor_temperature.0', 'motor_temperature.1', 'motor_temperature.2', 'motor_temperature.3', 'motor_temperature.4', 'motor_temperature.5']
  });
  assert.deepEqual(hazardFields(d), { present: true, x: 'x', y: 'y', radius: 'radius', count: 'hazard_count' });
  const bare = dictionary({ power: false, hazards: false });
  assert.equal(powerFields(bare).present, false);
  assert.equal(hazardFields(bare).present, false);
});

test('telemetry metadata: utc is the domain, met a value, numbers ranges, texts strings, codes enumerations', () => {
  const d = dictionary();
  const event = packetMetadata(d, 'EVENT').values;
  assert.deepEqual(event[0].hints, { domain: 1 });
  assert.equal(event[0].key, 'utc');
  assert.equal(event[1].key, 'met');
  const severity = event.find((v) => v.key === 'severity');
  assert.equal(severity.format, 'enum');
  assert.equal(severity.enumerations[3].string, 'ERROR');
  assert.equal(severity.min, 0);
  assert.equal(severity.max, 4);
  assert.equal(event.find((v) => v.key === 'text').format, 'string');
  assert.equal(event.find((v) => v.key === 'text').hints.range, undefined);
  const current = fieldMetadata(d, 'DRIVES', 'current.3').values;
  assert.equal(current.length, 3);
  assert.equal(current[2].name, 'current.3 (FR)');
  assert.equal(current[2].unit, 'A');
  assert.deepEqual(current[2].hints, { range: 1 });
  assert.equal(nameOf('DRIVES', 'state.2', 5), 'faulted');
  assert.equal(nameOf('DRIVES', 'state.2', 42), '42');
  assert.equal(enumerationsFor('ROVER_STATE', { key: 'x' }), undefined);
});

test('numbers show to five significant digits, integers whole', () => {
  assert.equal(formatNumber(3), '3');
  assert.equal(formatNumber(12.345678), '12.346');
  assert.equal(formatNumber(0.000123456), '0.00012346');
  assert.equal(formatNumber(1.7e9 + 0.5), '1700000000.5');
  assert.equal(formatNumber(2e-7), '2.000e-7');
  assert.equal(formatNumber(undefined), '');
});

const noTasks = { available: false, discover: async () => [] };

test('the root holds the views and one telemetry object per packet; POWER plots only with POWER', async () => {
  const d = dictionary();
  const objects = new RseObjects(d, noTasks);
  const root = await objects.get('root');
  const keys = root.composition.map((i) => i.key);
  for (const packet of d.packetNames()) assert.ok(keys.includes(`packet.${packet}`), packet);
  for (const view of ['overview', 'map', 'drive-health', 'mission-state', 'event-log', 'plot.position', 'plot.drive-currents', 'plot.battery', 'plot.motor-temperatures']) {
    assert.ok(keys.includes(view), view);
  }
  const bareKeys = (await new RseObjects(dictionary({ power: false }), noTasks).get('root')).composition.map((i) => i.key);
  assert.ok(!bareKeys.includes('plot.battery') && !bareKeys.includes('plot.motor-temperatures'));
  assert.equal(await objects.get('packet.NOPE'), undefined);
  assert.equal(await objects.get('field.DRIVES.nope'), undefined);
});

test('a ready-made plot has every series configured on its field object and axis', async () => {
  const plot = await new RseObjects(dictionary(), noTasks).get('plot.heading');
  assert.equal(plot.type, 'telemetry.plot.overlay');
  assert.deepEqual(plot.composition, [id('field.ROVER_STATE.heading'), id('field.ROVER_STATE.position_sigma')]);
  assert.deepEqual(plot.configuration.series.map((s) => [s.yKey, s.yAxisId]), [['heading', 1], ['position_sigma', 2]]);
  assert.deepEqual(plot.configuration.additionalYAxes, [{ id: 2 }]);
  const currents = await new RseObjects(dictionary(), noTasks).get('plot.drive-currents');
  assert.equal(currents.composition.length, 6);
  const field = await new RseObjects(dictionary(), noTasks).get('field.DRIVES.current.5');
  assert.deepEqual(field.rse, { packet: 'DRIVES', field: 'current.5' });
});

test('the event log shows time, severity, id and text; the overview lays out what exists', async () => {
  const objects = new RseObjects(dictionary(), noTasks);
  const log = await objects.get('event-log');
  assert.deepEqual(log.configuration.columnOrder, ['utc', 'severity', 'event_id', 'text']);
  assert.equal(log.configuration.hiddenColumns.severity, undefined);
  assert.equal(log.configuration.hiddenColumns.met, true);
  const overview = await objects.get('overview');
  const framed = overview.configuration.containers.flatMap((c) => c.frames.map((fr) => fr.domainObjectIdentifier.key));
  assert.deepEqual(overview.composition.map((i) => i.key), framed);
  assert.ok(framed.includes('map') && framed.includes('event-log') && framed.includes('plot.battery'));
  for (const c of overview.configuration.containers) {
    assert.ok(Math.abs(c.frames.reduce((s, fr) => s + fr.size, 0) - 100) < 1e-9);
  }
});

test('tasks are learnt from TASK_TIMING history and split by task index', async () => {
  const realtime = { subscribe: (packet, cb) => ((realtime.listener = cb), () => {}) };
  const history = async () => [
    { utc: 1, task_index: 1, task_name: 'can_io\0\0' },
    { utc: 2, task_index: 0, task_name: 'tables' }
  ];
  const tasks = new TaskDirectory({ dictionary: dictionary(), realtime, requestHistory: history, timeBounds: () => ({ start: 0, end: 10 }) });
  assert.deepEqual(await tasks.discover(), [{ index: 0, name: 'tables' }, { index: 1, name: 'can_io' }]);
  realtime.listener({ task_index: 7, task_name: 'habitual' });
  assert.equal(tasks.nameOf(7), 'habitual');
  const objects = new RseObjects(dictionary(), tasks);
  const plot = await objects.get('plot.task-cpu');
  assert.deepEqual(plot.configuration.series.map((s) => [s.identifier.key, s.yKey]), [['task.0', 'cpu_mean_us'], ['task.1', 'cpu_mean_us'], ['task.7', 'cpu_mean_us']]);
  const task = await objects.get('task.7');
  assert.deepEqual(task.rse, { packet: 'TASK_TIMING', taskIndex: 7 });
  assert.equal(task.name, 'habitual (task 7)');
});

// The display's own words where the dictionary's would not read as a value.
const DISPLAY_WORDING = { 'PLAN.call_home': { 0: 'no' } };

test('every coded value the display names is the one the flight dictionary describes', () => {
  const dictionary = JSON.parse(fs.readFileSync(new URL('../../../../docs/dictionary.json', import.meta.url), 'utf8'));
  for (const [key, names] of Object.entries(NAMES)) {
    const [packetName, fieldName] = key.split('.');
    const packet = dictionary.telemetry.find((p) => p.name === packetName);
    assert.ok(packet, `${key}: no packet ${packetName} in the dictionary`);
    const field = packet.fields.find((x) => x.name === fieldName);
    assert.ok(field, `${key}: no field ${fieldName} in ${packetName}`);
    // "0 SAFE, 1 STANDBY", "...: 0 nominal, 1 degraded", "0 boot-up wait .. 4 operational"
    const described = [...field.description.matchAll(/(?:^|[:,]|\.\.)\s*(\d+) ([A-Za-z][^,(:.]*)/g)];
    assert.ok(described.length >= 2, `${key}: its description names no values: ${field.description}`);
    for (const [, value, text] of described) {
      const i = Number(value);
      const want = DISPLAY_WORDING[key]?.[i];
      assert.ok(i < names.length, `${key}: the dictionary describes ${i} (${text.trim()}), the display has no name for it`);
      if (want !== undefined) {
        assert.equal(names[i], want, `${key} ${i}`);
      } else {
        assert.ok(text.trim().startsWith(names[i]), `${key} ${i}: the display says "${names[i]}", the dictionary "${text.trim()}"`);
      }
    }
  }
});


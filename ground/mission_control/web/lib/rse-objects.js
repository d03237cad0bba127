// The display's domain objects (namespace "rse"), all built from the display
// dictionary, none stored: the "RSE rover" root whose composition is the
// ready-made views and one telemetry object per packet; a telemetry point per
// field (what overlay plot series are made of: Open MCT draws one series per
// object); one telemetry object per rate-group task (TASK_TIMING split by its
// task index); the overview layout, the plots, the event log table and the
// custom views (map, drive health, mission state).

import { fieldMetadata, packetMetadata, displayName } from './telemetry-metadata.js';
import { powerFields } from './special-fields.js';
import { TASK_PACKET } from './task-directory.js';

export const NAMESPACE = 'rse';
export const ROOT_KEY = 'root';
export const OVERVIEW_KEY = 'overview';

export const TYPES = {
  packet: 'rse.packet',
  field: 'rse.field',
  task: 'rse.task',
  map: 'rse.map',
  driveHealth: 'rse.drive-health',
  missionState: 'rse.mission-state'
};

export function id(key) {
  return { namespace: NAMESPACE, key };
}

export function packetKey(packet) {
  return `packet.${packet}`;
}

export function fieldKey(packet, field) {
  return `field.${packet}.${field}`;
}

export function taskKey(index) {
  return `task.${index}`;
}

const ROOT_LOCATION = `${NAMESPACE}:${ROOT_KEY}`;

// Which TASK_TIMING value the task CPU plot draws: mean run time in host
// time when the dictionary has it, else the executive clock's.
const TASK_CPU_KEYS = ['cpu_mean_us', 'mean_us'];

export class RseObjects {
  constructor(dictionary, taskDirectory) {
    this.dictionary = dictionary;
    this.tasks = taskDirectory;
    this.power = powerFields(dictionary);
  }

  // The ready-made overlay plots: [{key, name, series: [{key, packet, field, axis}]}]
  // with only the series whose field the dictionary has; a plot with none is left out.
  plotDefinitions() {
    const d = this.dictionary;
    const series = (packet, fields, axis = 1) =>
      fields
        .filter((field) => field && d.field(packet, field))
        .map((field) => ({ key: fieldKey(packet, field), packet, field, axis }));
    const plots = [
      {
        key: 'plot.position',
        name: 'Position x, y',
        series: series('ROVER_STATE', ['x', 'y'])
      },
      {
        key: 'plot.heading',
        name: 'Heading and position sigma',
        series: [...series('ROVER_STATE', ['heading']), ...series('ROVER_STATE', ['position_sigma'], 2)]
      },
      { key: 'plot.speed', name: 'Speed', series: series('ROVER_STATE', ['speed']) },
      {
        key: 'plot.drive-currents',
        name: 'Drive currents',
        series: series('DRIVES', d.arrayKeys('DRIVES', 'current'))
      },
      {
        key: 'plot.motor-temperatures',
        name: 'Motor temperatures',
        series: series('POWER', this.power.motorTemperatures)
      },
      {
        key: 'plot.battery',
        name: 'Battery voltage and state of charge',
        series: [...series('POWER', [this.power.voltage]), ...series('POWER', [this.power.stateOfCharge], 2)]
      }
    ];
    return plots.filter((p) => p.series.length > 0);
  }

  taskCpuKey() {
    return TASK_CPU_KEYS.find((k) => this.dictionary.field(TASK_PACKET, k));
  }

  // Keys of the root's composition, in tree order.
  rootComposition() {
    const d = this.dictionary;
    const keys = [OVERVIEW_KEY, 'map', 'drive-health', 'mission-state'];
    if (d.hasPacket('EVENT')) keys.push('event-log');
    keys.push(...this.plotDefinitions().map((p) => p.key));
    if (this.tasks.available) keys.push('plot.task-cpu', 'tasks');
    keys.push(...d.packetNames().map(packetKey));
    return keys;
  }

  async get(key) {
    if (key === ROOT_KEY) return this.#folder(ROOT_KEY, this.dictionary.name, 'ROOT', this.rootComposition());
    if (key === OVERVIEW_KEY) return this.#overview();
    if (key === 'map') return this.#view(key, 'Map', TYPES.map);
    if (key === 'drive-health') return this.#view(key, 'Drive health', TYPES.driveHealth);
    if (key === 'mission-state') return this.#view(key, 'Mission state', TYPES.missionState);
    if (key === 'event-log') return this.#eventLog();
    if (key === 'tasks') {
      const tasks = await this.tasks.discover();
      return this.#folder('tasks', 'Tasks', ROOT_LOCATION, tasks.map((t) => taskKey(t.index)));
    }
    if (key === 'plot.task-cpu') return this.#taskCpuPlot();
    const plot = this.plotDefinitions().find((p) => p.key === key);
    if (plot) return this.#plot(plot.key, plot.name, plot.series);
    if (key.startsWith('packet.')) return this.#packet(key.slice('packet.'.length));
    if (key.startsWith('field.')) return this.#field(key);
    if (key.startsWith('task.')) return this.#task(Number(key.slice('task.'.length)));
    return undefined;
  }

  #folder(key, name, location, keys) {
    return { identifier: id(key), name, type: 'folder', location, composition: keys.map(id) };
  }

  #view(key, name, type) {
    return { identifier: id(key), name, type, location: ROOT_LOCATION };
  }

  #packet(name) {
    const packet = this.dictionary.packet(name);
    if (!packet) return undefined;
    return {
      identifier: id(packetKey(name)),
      name,
      type: TYPES.packet,
      location: ROOT_LOCATION,
      notes: packet.description,
      telemetry: packetMetadata(this.dictionary, name),
      rse: { packet: name }
    };
  }

  #field(key) {
    const rest = key.slice('field.'.length);
    const dot = rest.indexOf('.');
    const packet = rest.slice(0, dot);
    const fieldName = rest.slice(dot + 1);
    const field = this.dictionary.field(packet, fieldName);
    if (dot < 0 || !field) return undefined;
    return {
      identifier: id(key),
      name: `${packet} ${displayName(this.dictionary, packet, field)}`,
      type: TYPES.field,
      location: `${NAMESPACE}:${packetKey(packet)}`,
      notes: field.description,
      telemetry: fieldMetadata(this.dictionary, packet, fieldName),
      rse: { packet, field: fieldName }
    };
  }

  #task(index) {
    if (!this.tasks.available || !Number.isInteger(index)) return undefined;
    return {
      identifier: id(taskKey(index)),
      name: `${this.tasks.nameOf(index)} (task ${index})`,
      type: TYPES.task,
      location: `${NAMESPACE}:tasks`,
      telemetry: packetMetadata(this.dictionary, TASK_PACKET),
      rse: { packet: TASK_PACKET, taskIndex: index }
    };
  }

  // An overlay plot with every series configured, so Open MCT never has to
  // write its default series into these read-only objects.
  #plot(key, name, series) {
    const usesSecondAxis = series.some((s) => s.axis === 2);
    return {
      identifier: id(key),
      name,
      type: 'telemetry.plot.overlay',
      location: ROOT_LOCATION,
      composition: series.map((s) => id(s.key)),
      configuration: {
        series: series.map((s) => ({
          identifier: id(s.key),
          yKey: s.field,
          yAxisId: s.axis,
          interpolate: 'linear',
          markers: true,
          markerShape: 'point',
          markerSize: 2,
          alarmMarkers: true,
          limitLines: false
        })),
        yAxis: {},
        additionalYAxes: usesSecondAxis ? [{ id: 2 }] : [],
        xAxis: {},
        legend: { position: 'top', expandByDefault: false, showValueWhenExpanded: true }
      }
    };
  }

  async #taskCpuPlot() {
    const tasks = await this.tasks.discover();
    const yKey = this.taskCpuKey();
    const series = yKey
      ? tasks.map((t) => ({ key: taskKey(t.index), packet: TASK_PACKET, field: yKey, axis: 1 }))
      : [];
    const plot = this.#plot('plot.task-cpu', `Task CPU (${yKey || 'no timing field'} per task)`, series);
    return plot;
  }

  #eventLog() {
    const packet = this.dictionary.packet('EVENT');
    const shown = ['utc', 'severity', 'event_id', 'text'];
    // Open MCT adds a "<key>-unit" column beside each value with a unit.
    const hiddenColumns = { name: true, met: true, 'met-unit': true };
    for (const field of packet.fields) {
      if (!shown.includes(field.key)) hiddenColumns[field.key] = true;
      hiddenColumns[`${field.key}-unit`] = true;
    }
    return {
      identifier: id('event-log'),
      name: 'Event log',
      type: 'table',
      location: ROOT_LOCATION,
      composition: [id(packetKey('EVENT'))],
      configuration: {
        hiddenColumns,
        columnOrder: shown,
        // Fixed widths: autosized columns share the width equally and push
        // the text, the widest, out of a narrow frame.
        columnWidths: { utc: 200, severity: 75, event_id: 70, text: 600 },
        cellFormat: {},
        autosize: false,
        telemetryMode: 'unlimited',
        persistModeChange: false,
        rowLimit: 500
      }
    };
  }

  // The operator's first screen: map and mission state, the main plots, drive
  // health and the event log, side by side (a Flexible Layout fills the window).
  #overview() {
    const plots = new Set(this.plotDefinitions().map((p) => p.key));
    const frame = (key, size) => ({
      id: `frame-${key}`,
      domainObjectIdentifier: id(key),
      size,
      noFrame: false
    });
    const column = (name, size, frames) => ({ id: `column-${name}`, size, frames });
    const fill = (frames) => {
      const total = frames.reduce((sum, f) => sum + f.size, 0);
      return frames.map((f) => ({ ...f, size: (100 * f.size) / total }));
    };
    const plotFrames = ['plot.position', 'plot.drive-currents', 'plot.battery', 'plot.heading']
      .filter((k) => plots.has(k))
      .slice(0, 3)
      .map((k) => frame(k, 1));
    const rightFrames = [frame('drive-health', 42)];
    if (this.dictionary.hasPacket('EVENT')) rightFrames.push(frame('event-log', 58));
    const containers = [
      column('map', 36, [frame('map', 62), frame('mission-state', 38)]),
      column('plots', 27, fill(plotFrames)),
      column('health', 37, fill(rightFrames))
    ].filter((c) => c.frames.length > 0);
    const composition = containers.flatMap((c) => c.frames.map((f) => f.domainObjectIdentifier));
    return {
      identifier: id(OVERVIEW_KEY),
      name: 'Mission overview',
      type: 'flexible-layout',
      location: ROOT_LOCATION,
      composition,
      configuration: { rowsLayout: false, containers }
    };
  }
}

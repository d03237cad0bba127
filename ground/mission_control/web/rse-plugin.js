// The RSE plugin for Open MCT (docs/mission_control.md, "The browser side"):
// the display dictionary from rse-ground serve becomes the "RSE rover" root
// with a telemetry object per packet and the ready-made views; telemetry comes
// from /api/history (past) and the /realtime WebSocket (live); limits from the
// dictionary colour values out of range; and three custom views draw the map,
// the drive health and the mission state.

import { loadDictionary } from './lib/dictionary.js';
import { requestHistory } from './lib/history.js';
import { rseNumberFormat } from './lib/number-format.js';
import { RealtimeLink } from './lib/realtime.js';
import { id, NAMESPACE, ROOT_KEY, RseObjects, TYPES } from './lib/rse-objects.js';
import { TaskDirectory } from './lib/task-directory.js';
import { createTelemetryProvider } from './lib/telemetry-provider.js';
import { driveHealthViewProvider } from './views/drive-health-view.js';
import { mapViewProvider } from './views/map-view.js';
import { missionStateViewProvider } from './views/mission-state-view.js';

const TYPE_DEFINITIONS = [
  [TYPES.packet, 'RSE packet', 'One telemetry packet of the flight dictionary', 'icon-telemetry'],
  [TYPES.field, 'RSE telemetry point', 'One field of a telemetry packet', 'icon-telemetry'],
  [TYPES.task, 'RSE task timing', 'TASK_TIMING of one rate-group task', 'icon-telemetry'],
  [TYPES.map, 'RSE map', 'Site, rocks, hazards, plan and track', 'icon-image'],
  [TYPES.driveHealth, 'RSE drive health', 'State, mode estimate, current, temperature and faults per wheel', 'icon-tabular-lad'],
  [TYPES.missionState, 'RSE mission state', 'Mode, plan, executive, fault protection and link', 'icon-dataset']
];

export default function RsePlugin({ dictionaryUrl = '/api/dictionary', realtime = new RealtimeLink() } = {}) {
  return function install(openmct) {
    // Filled once the dictionary is loaded; every rse object waits for it, so
    // the views and providers below only run with it in place.
    const state = { dictionary: undefined, objects: undefined, tasks: undefined, realtime };
    const ready = loadDictionary(dictionaryUrl).then((dictionary) => {
      state.dictionary = dictionary;
      state.tasks = new TaskDirectory({
        dictionary,
        realtime,
        requestHistory,
        timeBounds: () => openmct.time.getBounds()
      });
      state.objects = new RseObjects(dictionary, state.tasks);
      return state;
    });
    ready.catch((error) => {
      console.error('RSE plugin: display dictionary', error);
      openmct.notifications.error(`RSE: cannot load the display dictionary (${error.message})`);
    });

    openmct.telemetry.addFormat(rseNumberFormat);
    for (const [key, name, description, cssClass] of TYPE_DEFINITIONS) {
      openmct.types.addType(key, { name, description, cssClass, creatable: false });
    }

    openmct.objects.addRoot(id(ROOT_KEY), openmct.priority.HIGH);
    openmct.objects.addProvider(NAMESPACE, {
      async get(identifier) {
        const { objects } = await ready;
        const object = await objects.get(identifier.key);
        if (!object) throw new Error(`no object ${NAMESPACE}:${identifier.key}`);
        return object;
      },
      // Everything here is made from the dictionary: nothing to save.
      isReadOnly: () => true
    });

    const telemetry = createTelemetryProvider({
      openmct,
      realtime,
      requestHistory,
      state
    });
    openmct.telemetry.addProvider(telemetry);

    openmct.objectViews.addProvider(mapViewProvider(openmct, state, TYPES.map));
    openmct.objectViews.addProvider(driveHealthViewProvider(openmct, state, TYPES.driveHealth));
    openmct.objectViews.addProvider(missionStateViewProvider(openmct, state, TYPES.missionState));

    // A packet opens as a table of all its fields (Open MCT would plot its
    // first number); the plot stays one click away in the view switcher.
    openmct.objectViews.addProvider({
      key: 'rse.packet-table',
      name: 'Packet table',
      cssClass: 'icon-tabular-scrolling',
      canView: (domainObject) => domainObject.type === TYPES.packet || domainObject.type === TYPES.task,
      view: (domainObject, objectPath) =>
        openmct.objectViews.getByProviderKey('table').view(domainObject, objectPath),
      priority: () => openmct.priority.HIGH
    });

    // For the operator's console and the browser test.
    openmct.rse = { state, ready };
  };
}

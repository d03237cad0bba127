// The Open MCT telemetry provider of the display's telemetry objects (packet,
// field and task objects, which all name their packet in domainObject.rse):
// history from /api/history, realtime from the one WebSocket, limits from the
// dictionary's field limits. A task object sees only the TASK_TIMING datums
// of its task.

import { fieldLimits, makeLimitDefinition, makeLimitEvaluator } from './limits.js';
import { NAMESPACE } from './rse-objects.js';
import { TASK_INDEX_KEY } from './task-directory.js';

function isRseTelemetry(domainObject) {
  return (
    domainObject?.identifier?.namespace === NAMESPACE &&
    Boolean(domainObject.telemetry) &&
    Boolean(domainObject.rse?.packet)
  );
}

function datumFilter(domainObject) {
  const index = domainObject.rse.taskIndex;
  if (index === undefined) {
    return () => true;
  }
  return (datum) => Number(datum[TASK_INDEX_KEY]) === index;
}

// state.dictionary is read at each call: it is loaded after the provider is registered.
export function createTelemetryProvider({ openmct, state, realtime, requestHistory }) {
  // Limits of the values an object shows: the packet's fields with limits, or
  // the one field of a field object.
  function limitsByKey(domainObject) {
    const { dictionary } = state;
    const { packet, field } = domainObject.rse;
    const fields = field
      ? [dictionary.field(packet, field)].filter(Boolean)
      : dictionary.packet(packet)?.fields || [];
    const map = new Map();
    for (const f of fields) {
      const limits = fieldLimits(packet, f);
      if (limits) map.set(f.key, limits);
    }
    return map;
  }

  return {
    supportsRequest: isRseTelemetry,
    async request(domainObject, options = {}) {
      // Open MCT fills start and end from the time conductor; a direct call may not.
      const bounds = openmct.time.getBounds();
      const start = options.start ?? bounds.start;
      const end = options.end ?? bounds.end;
      const datums = (
        await requestHistory(domainObject.rse.packet, start, end, { signal: options.signal })
      ).filter(datumFilter(domainObject));
      if (options.strategy === 'latest') {
        return datums.slice(-(options.size || 1));
      }
      if (options.enforceSize && options.size) {
        return datums.slice(-options.size);
      }
      return datums;
    },

    supportsSubscribe: isRseTelemetry,
    subscribe(domainObject, callback) {
      const accept = datumFilter(domainObject);
      return realtime.subscribe(domainObject.rse.packet, (datum) => {
        if (accept(datum)) callback(datum);
      });
    },

    supportsLimits: isRseTelemetry,
    getLimitEvaluator(domainObject) {
      return makeLimitEvaluator(limitsByKey(domainObject));
    },
    getLimits(domainObject) {
      return makeLimitDefinition(limitsByKey(domainObject));
    }
  };
}

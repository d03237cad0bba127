// Display limits: each field's {warn_low, warn_high, alarm_low, alarm_high}
// from the display dictionary, evaluated the way Open MCT's limit API expects
// (docs: API.md "Limit Evaluators"; the table, plot, LAD and layout views call
// evaluate(datum, valueMetadata) and colour by the returned cssClass). A value
// beyond an alarm limit is an alarm (red), beyond a warning limit a warning
// (yellow); a value on a limit is within it.

// Limits the display applies where the dictionary gives a field none: event
// severity WARN is a warning and ERROR / CRIT an alarm, so the event log is
// coloured by severity whatever the dictionary's limits hold.
const DEFAULT_LIMITS = {
  'EVENT.severity': { warn_high: 1, alarm_high: 2 }
};

const LEVELS = {
  alarm: { color: 'red', name: 'Alarm' },
  warning: { color: 'yellow', name: 'Warning' }
};

export function fieldLimits(packetName, field) {
  return field.limits || DEFAULT_LIMITS[`${packetName}.${field.key}`];
}

function finite(v) {
  return typeof v === 'number' && Number.isFinite(v);
}

// {level: 'alarm' | 'warning', side: 'high' | 'low'} or undefined (in limits,
// no limits, or no number).
export function limitState(value, limits) {
  const v = typeof value === 'string' ? Number(value) : value;
  if (!limits || !finite(v)) {
    return undefined;
  }
  if (finite(limits.alarm_high) && v > limits.alarm_high) return { level: 'alarm', side: 'high' };
  if (finite(limits.alarm_low) && v < limits.alarm_low) return { level: 'alarm', side: 'low' };
  if (finite(limits.warn_high) && v > limits.warn_high) return { level: 'warning', side: 'high' };
  if (finite(limits.warn_low) && v < limits.warn_low) return { level: 'warning', side: 'low' };
  return undefined;
}

// The CSS class Open MCT's stylesheets colour a limit violation with.
export function limitCssClass(state) {
  if (!state) return '';
  const side = state.side === 'high' ? 'is-limit--upr' : 'is-limit--lwr';
  return `${side} is-limit--${LEVELS[state.level].color}`;
}

function evaluation(state, limits) {
  const low = state.level === 'alarm' ? limits.alarm_low : limits.warn_low;
  const high = state.level === 'alarm' ? limits.alarm_high : limits.warn_high;
  return {
    cssClass: limitCssClass(state),
    name: `${LEVELS[state.level].name} ${state.side === 'high' ? 'High' : 'Low'}`,
    low: finite(low) ? low : Number.NEGATIVE_INFINITY,
    high: finite(high) ? high : Number.POSITIVE_INFINITY
  };
}

// limitsByKey: Map key -> limits for the values of one telemetry object.
// evaluate(datum, valueMetadata) judges that value; without valueMetadata (a
// table row) it judges the worst of all, so a row shows its worst field.
export function makeLimitEvaluator(limitsByKey) {
  return {
    evaluate(datum, valueMetadata) {
      if (!datum) return undefined;
      if (valueMetadata) {
        const limits = limitsByKey.get(valueMetadata.key);
        const state = limitState(datum[valueMetadata.source || valueMetadata.key], limits);
        return state ? evaluation(state, limits) : undefined;
      }
      let worst;
      for (const [key, limits] of limitsByKey) {
        const state = limitState(datum[key], limits);
        if (state && (!worst || (state.level === 'alarm' && worst.state.level !== 'alarm'))) {
          worst = { state, limits };
        }
      }
      return worst ? evaluation(worst.state, worst.limits) : undefined;
    }
  };
}

// Limit lines for plots (Open MCT's getLimits): per level a low and a high
// object holding the limit of every value key that has one.
export function makeLimitDefinition(limitsByKey) {
  const levels = {};
  const put = (levelName, side, color, key, value) => {
    if (!finite(value)) return;
    levels[levelName] = levels[levelName] || {};
    levels[levelName][side] = levels[levelName][side] || { color };
    levels[levelName][side][key] = value;
  };
  for (const [key, limits] of limitsByKey) {
    put('WARNING', 'low', 'yellow', key, limits.warn_low);
    put('WARNING', 'high', 'yellow', key, limits.warn_high);
    put('CRITICAL', 'low', 'red', key, limits.alarm_low);
    put('CRITICAL', 'high', 'red', key, limits.alarm_high);
  }
  return {
    limits: () => Promise.resolve(Object.keys(levels).length ? levels : undefined)
  };
}

// Open MCT telemetry format "rse.number": integers as they are, other numbers
// to five significant digits (fixed-point, never exponent notation, for
// values from 1e-4 upward), so tables and legends stay readable whatever the
// field's type. Registered with openmct.telemetry.addFormat.

export const RSE_NUMBER_FORMAT = 'rse.number';

export function formatNumber(value) {
  const v = typeof value === 'string' ? Number(value) : value;
  if (typeof v !== 'number' || Number.isNaN(v)) {
    return value === undefined || value === null ? '' : String(value);
  }
  if (Number.isInteger(v) || !Number.isFinite(v)) {
    return String(v);
  }
  const magnitude = Math.abs(v);
  if (magnitude >= 1e4) {
    return v.toFixed(1);
  }
  if (magnitude < 1e-4) {
    return v.toExponential(3);
  }
  return String(Number(v.toPrecision(5)));
}

export const rseNumberFormat = {
  key: RSE_NUMBER_FORMAT,
  format: formatNumber,
  parse: (text) => (typeof text === 'number' ? text : Number(text)),
  validate: (text) => !Number.isNaN(Number(text))
};

// Small DOM helpers shared by the custom views.

const SVG_NS = 'http://www.w3.org/2000/svg';

function apply(node, attributes, children) {
  for (const [name, value] of Object.entries(attributes || {})) {
    if (value === undefined || value === null || value === false) continue;
    if (name === 'text') node.textContent = String(value);
    else node.setAttribute(name, String(value));
  }
  for (const child of children || []) {
    if (child !== undefined && child !== null) node.append(child);
  }
  return node;
}

export function html(tag, attributes, children) {
  return apply(document.createElement(tag), attributes, children);
}

export function svg(tag, attributes, children) {
  return apply(document.createElementNS(SVG_NS, tag), attributes, children);
}

// "12:34:56" UTC of a datum's receive time.
export function timeOfDay(utc) {
  return Number.isFinite(utc) ? new Date(utc).toISOString().slice(11, 19) : '—';
}

export function fixed(value, decimals) {
  const v = Number(value);
  return value === undefined || value === null || !Number.isFinite(v) ? '—' : v.toFixed(decimals);
}

// Bit n of an unsigned integer up to 2^53 (JavaScript's bit operators stop at 32 bits).
export function bit(value, n) {
  const v = Number(value);
  return Number.isFinite(v) && Math.floor(v / 2 ** n) % 2 === 1;
}

// The length of every JavaScript function in the files named on the command
// line, for the house rules test (house_rules_test.sh): one line per function,
//   END START FILE NAME
// (the lines it spans, from its first to its closing brace, as the test reads
// universal-ctags' C++ measure), parsed with acorn (ground/mission_control/web's
// pinned devDependency: make mission-control-deps installs it). A function
// nested in another counts in it too, as a lambda counts in its C++ function.
// Exit status 2 when acorn is missing or a file does not parse, with the reason.
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';
import { resolve } from 'node:path';

const webPackage = resolve(process.cwd(), 'ground/mission_control/web/package.json');
let acorn;
try {
  acorn = createRequire(webPackage)('acorn');
} catch (e) {
  console.error(`js_function_lengths: acorn is not installed (make mission-control-deps): ${e.message}`);
  process.exit(2);
}

// The name a function goes by: its own, its method's (Class.method), or the
// variable or property it is assigned to.
function nameOf(node, parent, className) {
  if (node.id && node.id.name) return node.id.name;
  if (parent && parent.type === 'MethodDefinition') {
    const key = parent.key.name ?? (parent.key.type === 'PrivateIdentifier' ? `#${parent.key.name}` : '?');
    return `${className ?? '(class)'}.${parent.key.type === 'PrivateIdentifier' ? '#' : ''}${key}`;
  }
  if (parent && parent.type === 'VariableDeclarator' && parent.id.name) return parent.id.name;
  if (parent && parent.type === 'Property' && parent.key && (parent.key.name || parent.key.value)) {
    return String(parent.key.name ?? parent.key.value);
  }
  return '(anonymous)';
}

const FUNCTIONS = new Set(['FunctionDeclaration', 'FunctionExpression', 'ArrowFunctionExpression']);

function walk(node, parent, className, file, out) {
  if (!node || typeof node.type !== 'string') return;
  let cls = className;
  if (node.type === 'ClassDeclaration' || node.type === 'ClassExpression') {
    cls = node.id ? node.id.name : className;
  }
  if (FUNCTIONS.has(node.type)) {
    out.push(`${node.loc.end.line} ${node.loc.start.line} ${file} ${nameOf(node, parent, cls)}`);
  }
  for (const key of Object.keys(node)) {
    if (key === 'loc' || key === 'start' || key === 'end') continue;
    const child = node[key];
    if (Array.isArray(child)) {
      for (const c of child) walk(c, node, cls, file, out);
    } else if (child && typeof child.type === 'string') {
      walk(child, node, cls, file, out);
    }
  }
}

const out = [];
for (const file of process.argv.slice(2)) {
  let tree;
  try {
    tree = acorn.parse(readFileSync(file, 'utf8'), {
      ecmaVersion: 'latest',
      sourceType: 'module',
      locations: true,
      allowHashBang: true
    });
  } catch (e) {
    console.error(`js_function_lengths: ${file} does not parse: ${e.message}`);
    process.exit(2);
  }
  walk(tree, null, undefined, file, out);
}
console.log(out.join('\n'));

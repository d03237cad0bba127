#!/usr/bin/env bash
# The size of the rooms (issue 30, docs/architecture.md "A map for a newcomer"):
#   - no source file in fsw/, hal/, ground/ or sim_stub/ over MAX_FILE_LINES (800) lines:
#     C++ (.cpp, .hpp), JavaScript (.js, .mjs) and shell (.sh); generated files
#     (none are kept in these folders: they go to build/) and the dictionary and table
#     definitions (.def: one entry a line, read by X-macros) are not code to split;
#   - no function there over MAX_FUNCTION_LINES (100) lines, from its first line
#     to its closing brace: C++ as universal-ctags measures it (kind f: functions
#     and member functions defined in .cpp and .hpp files; a lambda counts in the
#     function that holds it), JavaScript as acorn parses it
#     (js_function_lengths.mjs: functions, methods and arrow functions; a nested
#     one counts in its holder too).
# It prints, for each folder, its largest file and its longest function (the
# figures a newcomer, and the issue's closing note, wants), every breach, and
# "N passed, N failed": one check per file and per function measured, plus one
# that the measurement saw the code (a ctags that found nothing fails).
#
# Host only: it reads the sources, and needs universal-ctags (Debian's
# universal-ctags, in make deps) and, for the JavaScript, Node.js with the
# display's npm packages (make mission-control-deps, which make test runs first).
set -u
# The repository root: the first folder up from this script with the Makefile and fsw/
# (unit_test/ mirrors fsw/, so fsw/ alone would stop there).
cd "$(dirname "$0")" && while { [ ! -d fsw ] || [ ! -f Makefile ]; } && [ "$PWD" != / ]; do cd ..; done
MAX_FILE_LINES=${MAX_FILE_LINES:-800}
MAX_FUNCTION_LINES=${MAX_FUNCTION_LINES:-100}
ROOTS="fsw hal ground sim_stub"
passed=0 failed=0

if ! ctags --version 2>/dev/null | grep -q "Universal Ctags"; then
  echo "FAIL: universal-ctags is not installed (make deps installs it)"
  echo "0 passed, 1 failed"
  exit 1
fi

# Every source file, with the folder it belongs to (its directory).
files=$(git ls-files -- $ROOTS 2>/dev/null | grep -E '\.(cpp|hpp|js|mjs|sh)$' | grep -v '/node_modules/')
if [ -z "$files" ]; then
  files=$(find $ROOTS -path '*/node_modules' -prune -o -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.js' \
          -o -name '*.mjs' -o -name '*.sh' \) -print)
fi

echo "files (limit $MAX_FILE_LINES lines)"
file_table=$(for f in $files; do printf '%s %s %s\n' "$(dirname "$f")" "$(wc -l < "$f")" "$f"; done)
while read -r dir lines f; do
  if [ "$lines" -gt "$MAX_FILE_LINES" ]; then
    echo "  FAIL: $f has $lines lines (limit $MAX_FILE_LINES)"; failed=$((failed + 1))
  else
    passed=$((passed + 1))
  fi
done <<< "$file_table"

echo "functions (C++ and JavaScript, limit $MAX_FUNCTION_LINES lines)"
cpp_files=$(printf '%s\n' $files | grep -E '\.(cpp|hpp)$')
fn_table=$(printf '%s\n' $cpp_files | ctags --languages=C++ --kinds-C++=f --fields=+ne -x \
             --_xformat='%{end} %{line} %{input} %{scope}::%{name}' -L - 2>/dev/null |
           awk '$1 ~ /^[0-9]+$/ { n = $1 - $2 + 1; f = $3; sub(/^::/, "", $4); gsub(/__anon[0-9a-f]+::/, "(anonymous)::", $4); d = f; sub(/\/[^\/]*$/, "", d); print d, n, f ":" $2, $4 }')
js_files=$(printf '%s\n' $files | grep -E '\.(js|mjs)$')
if js_out=$(node unit_test/system/layering/js_function_lengths.mjs $js_files 2>&1); then
  fn_table="$fn_table
$(printf '%s\n' "$js_out" | awk '$1 ~ /^[0-9]+$/ { n = $1 - $2 + 1; f = $3; d = f; sub(/\/[^\/]*$/, "", d); print d, n, f ":" $2, $4 }')"
  passed=$((passed + 1))
else
  echo "  FAIL: the JavaScript functions could not be measured: $js_out"
  failed=$((failed + 1))
fi
fn_count=$(printf '%s\n' "$fn_table" | grep -c . )
if [ "$fn_count" -lt 500 ]; then
  echo "  FAIL: ctags measured only $fn_count functions (the code has thousands): the measurement is broken"
  failed=$((failed + 1))
else
  passed=$((passed + 1))
fi
while read -r dir n where name; do
  [ -n "$dir" ] || continue
  if [ "$n" -gt "$MAX_FUNCTION_LINES" ]; then
    echo "  FAIL: $name ($where) has $n lines (limit $MAX_FUNCTION_LINES)"; failed=$((failed + 1))
  else
    passed=$((passed + 1))
  fi
done <<< "$fn_table"

echo "largest file and longest function per folder"
printf "  %-34s %-44s %s\n" "folder" "largest file (lines)" "longest function (lines)"
for dir in $(printf '%s\n' "$file_table" | awk '{print $1}' | sort -u); do
  big=$(printf '%s\n' "$file_table" | awk -v d="$dir" '$1 == d' | sort -k2,2n | tail -1 | awk '{n = split($3, p, "/"); print p[n] " (" $2 ")"}')
  long=$(printf '%s\n' "$fn_table" | awk -v d="$dir" '$1 == d' | sort -k2,2n | tail -1 | awk '{print $4 " (" $2 ")"}')
  printf "  %-34s %-44s %s\n" "$dir" "$big" "${long:--}"
done
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

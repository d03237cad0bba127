#!/usr/bin/env bash
# rse-ground's command line as a user meets it (docs/operations.md, "Command
# lines"): --help on stdout (exit 0), a bad command line as one line naming what
# is wrong plus "see 'rse-ground --help'" on stderr (exit 2, nothing on stdout),
# and the offline commands that need no rover. Ends with "N passed, N failed".
#
# env: RSE_BIN_DIR (where rse-ground is). Host only: rse-ground is a host tool.
set -u
bin="${RSE_BIN_DIR:?set RSE_BIN_DIR}/rse-ground"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0 failed=0
export RSE_GROUND_STATE="$work/state"  # never the user's anti-replay numbers

check() {  # check NAME CONDITION-COMMAND...
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); echo "  pass: $name"
  else failed=$((failed + 1)); echo "  FAIL: $name"; fi
}
ground() { "$bin" "$@" >"$work/out" 2>"$work/err"; rc=$?; }
# bad_line NAME WORDS... : exit 2, stdout empty, two lines on stderr, the second the --help pointer.
bad_line() {
  local name=$1; shift
  ground "$@"
  check "$name: exit 2" test "$rc" -eq 2
  check "$name: nothing on stdout" test ! -s "$work/out"
  check "$name: two lines on stderr, then see --help" \
    sh -c "[ \$(wc -l < '$work/err') -eq 2 ] && tail -n 1 '$work/err' | grep -qx \"rse-ground: see 'rse-ground --help'\""
}

echo "rse-ground --help"
for help in "--help" "-h" "help" "send --help" "table build -h" "plan check --help" "--timeout 3 watch --help"; do
  # shellcheck disable=SC2086  # the words of $help are the command line
  ground $help
  check "'$help': exit 0, the usage on stdout, nothing on stderr" \
    sh -c "[ $rc -eq 0 ] && grep -q '^usage: rse-ground' '$work/out' && [ ! -s '$work/err' ]"
done
ground --help
for option in --udp --tlm-port --can --can-tx --can-rx --pad --key-file --key-id --no-auth --state-dir --timeout \
              --auth-seq --no-wait --count --seconds --only --until-outcome --tail --quiet --facts --no-events \
              --map --tables --out --name --verbose --activate --force --inactive --cpp --markdown --json \
              --failed --degraded --http --archive --web; do
  check "the usage names $option" grep -q -- "$option" "$work/out"
done

echo "a bad command line"
bad_line "an unknown global option" --no-such-option send NOOP
check "an unknown global option is named" grep -q "rse-ground: unknown option --no-such-option" "$work/err"
bad_line "an unknown command" launch
check "an unknown command is named" grep -q "unknown command 'launch'" "$work/err"
bad_line "no command"
bad_line "an unknown option of a command" send NOOP --bogus
check "the command and the option are named" grep -q "send: unknown option --bogus" "$work/err"
bad_line "a global option after the command" send NOOP --timeout 1
check "it says where global options go" grep -q -- "--timeout is a global option: give it before the command" "$work/err"
bad_line "a missing value" watch --count
check "the option without its value is named" grep -q -- "watch: --count needs a value" "$work/err"
bad_line "a value that is not a number" --timeout soon send NOOP
check "the option and the value are named" grep -q -- "--timeout 'soon': expected seconds" "$work/err"
bad_line "a value out of range" --can-tx 800 send NOOP
bad_line "a flag given a value" send NOOP --no-wait=yes
check "the flag is named" grep -q -- "--no-wait takes no value" "$work/err"
bad_line "conflicting options" dict --json --markdown
bad_line "a command argument out of range" send GOTO x=1 y=2 risk=2
check "the argument is named" grep -q "GOTO: risk=2 is out of range" "$work/err"
bad_line "an operand too many" summary a.rec b.rec
check "the operand is named" grep -q "summary: unexpected 'b.rec'" "$work/err"
bad_line "an unknown table sub-command" table frobnicate
bad_line "table build without -o" table build tables/rover_geometry.toml
bad_line "an unknown plan component" plan check unit_test/fuzz/corpus/plan/two_targets.plan --failed laser
check "the component is named" grep -q "plan check: unknown component 'laser'" "$work/err"

echo "offline commands (no rover)"
ground table build tables/rover_geometry.toml -o "$work/geometry.tbl"
check "table build: exit 0, the image written" sh -c "[ $rc -eq 0 ] && [ -s '$work/geometry.tbl' ]"
ground table check "$work/geometry.tbl"
check "table check: exit 0, ok" sh -c "[ $rc -eq 0 ] && grep -q ': ok, ROVER_GEOMETRY' '$work/out'"
ground dict --json -o "$work/dict.json"
check "dict --json -o: exit 0, the file written" sh -c "[ $rc -eq 0 ] && grep -q '\"format\": \"rse-dictionary\"' '$work/dict.json'"
ground encode NOOP --auth-seq 7 -o "$work/noop.bin"
check "encode -o: exit 0, says what it wrote" sh -c "[ $rc -eq 0 ] && grep -q 'NOOP, .* auth seq 7' '$work/out'"
ground plan check unit_test/fuzz/corpus/plan/two_targets.plan --degraded camera
check "plan check: exit 0, the selection printed" sh -c "[ $rc -eq 0 ] && grep -q '^selection: ' '$work/out'"
ground --udp 127.0.0.1:9 --tlm-port 127.0.0.1:0 --timeout 0.2 send NOOP
check "send with no rover: exit 1, no acknowledgement" sh -c "[ $rc -eq 1 ] && grep -q 'no acknowledgement within 0.2 s' '$work/err'"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

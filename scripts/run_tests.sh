#!/usr/bin/env bash
# Every test, as `make test` runs them (in a sourced workspace, after the lint): the ROS integration tests one at a
# time in the foreground, each playing in real time with the CPU it needs; beside them, at a lower priority
# (nice 10), the unit tests on every core, in the CPU time the integration tests leave idle (about half of two
# cores). The unit tests' report follows the integration tests'; the status is that of the first suite to fail.
set -uo pipefail
cd "$(dirname "$0")/.."

unit_log="$(mktemp -t nubot-unit-tests.XXXXXX.log)"
nice -n 10 python -m pytest -m "not integration" -n auto --dist loadfile > "$unit_log" 2>&1 &
unit_pid=$!
trap 'kill -INT "$unit_pid" 2>/dev/null; wait "$unit_pid" 2>/dev/null' INT TERM
echo "[test] unit tests running in the background (nice 10, every core), their report at the end: $unit_log"

python -m pytest -m integration
integration=$?

if kill -0 "$unit_pid" 2>/dev/null; then
  echo "[test] waiting for the unit tests"
fi
wait "$unit_pid"
unit=$?
trap - INT TERM
echo "[test] the unit tests' report:"
cat "$unit_log"
echo "[test] unit tests: exit status $unit; integration tests: exit status $integration"
if [ "$unit" -ne 0 ]; then
  exit "$unit"
fi
exit "$integration"

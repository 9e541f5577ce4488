#!/usr/bin/env bash
# Every test, as `make test` runs them (in a sourced workspace): the ROS integration tests one at a time in the
# foreground, each playing in real time with the CPU it needs; beside them, at a lower priority (nice 10), the lint
# (scripts/lint.sh) and the unit tests on every core, in the CPU time the integration tests leave idle (about half
# of two cores). Their reports follow the integration tests'; the status is that of the first to fail (lint, unit,
# integration).
set -uo pipefail
cd "$(dirname "$0")/.."

lint_log="$(mktemp -t nubot-lint.XXXXXX.log)"
nice -n 10 bash scripts/lint.sh > "$lint_log" 2>&1 &
lint_pid=$!
unit_log="$(mktemp -t nubot-unit-tests.XXXXXX.log)"
# the training test needs make train's libraries: installed here (once), beside the integration tests
nice -n 10 bash -c 'bash scripts/setup_train.sh && exec python -m pytest -m "not integration" -n auto --dist loadfile' \
  > "$unit_log" 2>&1 &
unit_pid=$!
trap 'kill -INT "$unit_pid" "$lint_pid" 2>/dev/null; wait "$unit_pid" "$lint_pid" 2>/dev/null' INT TERM
echo "[test] lint and unit tests running in the background (nice 10, every core), their reports at the end:" \
  "$lint_log, $unit_log"

python -m pytest -m integration
integration=$?

if kill -0 "$unit_pid" 2>/dev/null; then
  echo "[test] waiting for the unit tests"
fi
wait "$unit_pid"
unit=$?
wait "$lint_pid"
lint=$?
trap - INT TERM
echo "[test] the lint's report:"
cat "$lint_log"
echo "[test] the unit tests' report:"
cat "$unit_log"
echo "[test] lint: exit status $lint; unit tests: exit status $unit; integration tests: exit status $integration"
for status in "$lint" "$unit"; do
  if [ "$status" -ne 0 ]; then
    exit "$status"
  fi
done
exit "$integration"

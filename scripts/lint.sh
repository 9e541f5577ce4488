#!/usr/bin/env bash
# The lint, as `make lint` and `make test` run it: ruff on every Python file, mypy on the cores (setup.cfg).
set -euo pipefail
cd "$(dirname "$0")/.."
.venv/bin/ruff check src scripts
mypy --python-executable .venv/bin/python

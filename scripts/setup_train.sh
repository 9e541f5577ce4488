#!/usr/bin/env bash
# What `make train` adds to the workspace's .venv, idempotently: requirements-train.txt (PyTorch's CPU build,
# Stable-Baselines3, TensorBoard). Debian's numpy, scipy and matplotlib stay as they are (the compiled Debian
# packages are built against them); skipped when the file's hash matches the last install.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
log() { printf '[setup_train] %s\n' "$*"; }
req_hash="$(sha256sum requirements-train.txt | cut -d' ' -f1)"
if [ "$(cat .venv/.requirements-train.sha256 2>/dev/null || true)" = "$req_hash" ]; then
  log "training libraries present"
  exit 0
fi
log "installing the training libraries into .venv (requirements-train.txt: about 800 MB, once)"
keep="$(mktemp)"
trap 'rm -f "$keep"' EXIT
.venv/bin/python -m pip freeze --disable-pip-version-check 2>/dev/null \
  | grep -E '^(numpy|scipy|matplotlib|Pillow)==' > "$keep" || true
.venv/bin/python -m pip install -q --disable-pip-version-check -r requirements-train.txt -c "$keep"
.venv/bin/python -c "import torch, stable_baselines3; print('[setup_train] torch', torch.__version__, \
'stable-baselines3', stable_baselines3.__version__)"
echo "$req_hash" > .venv/.requirements-train.sha256

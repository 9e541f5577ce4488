#!/usr/bin/env bash
# Prepare this workspace on Debian 12, idempotently: Debian packages (ROS 1,
# ODE, numpy/scipy/matplotlib), the .venv for what Debian lacks, and catkin_make.
# Every step is skipped when its result is already there.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

log() { printf '[setup] %s\n' "$*"; }

mapfile -t debs < <(grep -v '^\s*#' scripts/debian-packages.txt | grep -v '^\s*$')
missing=()
for p in "${debs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  log "installing ${#missing[@]} Debian packages: ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  log "Debian packages present"
fi

if [ ! -x .venv/bin/python ]; then
  log "creating .venv (system site packages visible)"
  /usr/bin/python3 -m venv --system-site-packages .venv
fi
req_hash="$(sha256sum requirements.txt | cut -d' ' -f1)"
if [ "$(cat .venv/.requirements.sha256 2>/dev/null || true)" != "$req_hash" ]; then
  log "installing Python requirements into .venv"
  .venv/bin/python -m pip install -q --disable-pip-version-check -r requirements.txt
  echo "$req_hash" > .venv/.requirements.sha256
else
  log ".venv up to date"
fi

# The packages' pure modules, importable from the .venv without sourcing devel/setup.bash (the match
# report works from a bag alone); a sourced workspace puts devel first, with the generated messages.
site="$(.venv/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
ls -d "$root"/src/*/src > "$site/nubot_ws.pth"

# DAQP's C sources for the MPC's QP solver (nubot_control's kernels), from its pinned PyPI source release: the
# solver is not packaged by Debian, and this is the release the Python MPC was held to.
daqp_version=0.11.0
daqp_sha256=2f27baf18d2acca14186498e651b34e0bed455627e777d3fd8ba655e7e40f920
daqp_dir=".third_party/daqp-$daqp_version"
if [ ! -f "$daqp_dir/csrc/src/daqp.c" ]; then
  log "fetching DAQP $daqp_version's C sources (PyPI source release)"
  download="$(mktemp -d)"
  # --no-binary daqp, not :all:, which would build pip's metadata step's own tools (setuptools, Cython) from
  # source too: minutes instead of seconds
  .venv/bin/python -m pip download -q --disable-pip-version-check --no-deps --no-binary daqp \
    -d "$download" "daqp==$daqp_version"
  archive="$download/daqp-$daqp_version.tar.gz"
  if [ "$(sha256sum "$archive" | cut -d' ' -f1)" != "$daqp_sha256" ]; then
    log "DAQP's source release does not match its pinned sha256: $archive"
    exit 1
  fi
  mkdir -p .third_party
  tar -xzf "$archive" -C .third_party
  rm -rf "$download"
else
  log "DAQP's C sources present"
fi

log "catkin_make"
# The messages are generated for Python and C++ (the original's C++ nodes), not for Lisp, which nothing here uses
export ROS_LANG_DISABLE=genlisp
if ! catkin_make -DPYTHON_EXECUTABLE="$PWD/.venv/bin/python" -DCMAKE_BUILD_TYPE=Release > .catkin_make.log 2>&1; then
  tail -n 40 .catkin_make.log
  log "catkin_make failed (full log: .catkin_make.log)"
  exit 1
fi
log "workspace ready: source devel/setup.bash"

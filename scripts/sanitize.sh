#!/usr/bin/env bash
# make sanitize: the compiled kernels built with AddressSanitizer and UndefinedBehaviorSanitizer (their own build
# folder, build/sanitize; the normal kernels stay as they are), then the unit tests of the pieces they hold run on
# them. Any error a sanitizer finds stops the run with its report.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

build="$root/build/sanitize"
kernels="$build/kernels"
targets=(nubot_control_kernels world_model_kernels sim_visual_kernels)
# The unit tests of what the kernels compute (and of their loader).
tests=(src/nubot_control/test/unit/test_mpc.py src/nubot_control/test/unit/test_path_planning.py
       src/nubot_control/test/unit/test_kernels.py src/nubot_control/test/unit/test_motion.py
       src/nubot_control/test/unit/test_chances.py
       src/world_model/test/unit/test_obstacles.py src/world_model/test/unit/test_ball_fusion.py
       src/world_model/test/unit/test_world_model.py src/world_model/test/unit/test_sensor_fusion.py
       src/world_model/test/unit/test_world_model_golden.py
       src/sim_visual/test/unit/test_physics_golden.py src/sim_visual/test/unit/test_simulator.py
       src/sim_visual/test/unit/test_sensing_golden.py src/sim_visual/test/unit/test_sensing.py
       src/sim_visual/test/unit/test_stuck_golden.py src/sim_visual/test/unit/test_robot_limits.py
       src/sim_visual/test/unit/test_ball_handler_golden.py src/sim_visual/test/unit/test_rules.py
       src/sim_visual/test/unit/test_cameras_golden.py src/sim_visual/test/unit/test_front_camera.py
       src/sim_visual/test/unit/test_rgbd_camera.py)

echo "[sanitize] building ${targets[*]} with -fsanitize=address,undefined into $kernels"
if ! catkin_make --build "$build" -DCATKIN_DEVEL_PREFIX="$build/devel" -DNUBOT_SANITIZE=ON \
     -DNUBOT_KERNELS_DIR="$kernels" -DPYTHON_EXECUTABLE="$root/.venv/bin/python" -DCMAKE_BUILD_TYPE=Debug \
     "${targets[@]}" > "$build.log" 2>&1; then
  tail -n 40 "$build.log"
  echo "[sanitize] the build failed (full log: $build.log)"
  exit 1
fi

# Python itself is not built with the sanitizers: their runtimes are preloaded; Python's own allocations at exit
# are not the kernels' leaks, so the leak check is off.
export LD_PRELOAD="$(gcc -print-file-name=libasan.so) $(gcc -print-file-name=libubsan.so)"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:halt_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export NUBOT_KERNELS_PATH="$kernels"
python -c "import sys, nubot_control.mpc as a, world_model.obstacles as b, sim_visual.world as c; \
files = [a._kernels.__file__, b._kernels.__file__, c._kernels.__file__]; print('[sanitize] kernels:', *files); \
sys.exit(0 if all(f.startswith('$kernels') for f in files) else 'the sanitized kernels were not loaded')"
python -m pytest -q -p no:randomly "${tests[@]}"

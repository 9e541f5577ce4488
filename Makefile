# The two commands: `make match` and `make test`. Each prepares the workspace first.
SHELL := /bin/bash
ROS := source devel/setup.bash &&
HALF_SECONDS ?= 90
TRACKER ?= mpc
FIELD ?= 18x12
DEMO_SECONDS ?= 60
SOAK_HALF_SECONDS ?= 900
HOME_TEAM_DEFAULT := src/nubot_control/config/teams/nubot.yaml
AWAY_TEAM_DEFAULT := src/nubot_control/config/teams/rival.yaml
MATCHES ?= 40
SEED ?= 0
SEEDS ?= 4
VISION ?=
VIEWER_PORT ?= 8080
POLICY ?=
POLICY_ROBOTS ?= 2
TASK ?= score
STEPS ?= 2000000
EPISODES ?= 200

.PHONY: setup match demo replay evaluate train test unit integration bench soak lint clean
.PHONY: bench-faithfulness sanitize

setup:
	@bash scripts/setup.sh

match: setup
	@$(ROS) python scripts/run_match.py --half-seconds $(HALF_SECONDS) --tracker $(TRACKER) --field $(FIELD) \
	  --vision "$(VISION)" --viewer-port $(VIEWER_PORT) \
	  $(if $(POLICY),--policy "$(POLICY)" --policy-robots "$(POLICY_ROBOTS)",)

demo: setup
	@$(ROS) python scripts/run_demo.py --sim-seconds $(DEMO_SECONDS)

# The live page over a recorded match: make replay BAG=matches/match-<time>/match.bag [PORT=8080]
replay: setup
	@test -n "$(BAG)" || { echo "make replay BAG=<a match bag>, e.g. matches/match-<time>/match.bag"; exit 2; }
	@$(ROS) python scripts/replay.py "$(BAG)" --port $(or $(PORT),8080)

# With POLICY=<file> (make train's policy.npz): that policy against the scripted striker on its TASK, EPISODES seeded
# episodes each (evaluations/<task>-<time>/{results.json,table.md,success.png}). Otherwise:
# many lockstep matches, HOME against AWAY, on every core (JOBS=N) or a dask cluster (SCHEDULER=tcp://host:8786):
# evaluations/<time>/{results.json,table.md,goal_difference.png}. HOME is also the shell's home folder: only a
# HOME given on the command line names a team.
evaluate: setup
ifneq ($(POLICY),)
	@$(ROS) python scripts/evaluate.py --policy "$(POLICY)" --task $(TASK) --episodes $(EPISODES) --seed $(SEED) \
	  $(if $(JOBS),--jobs $(JOBS),) $(if $(OUT),--out $(OUT),)
else
	@export HOME=$$(getent passwd $$(id -u) | cut -d: -f6) && $(ROS) python scripts/evaluate.py \
	  --home $(if $(filter command line,$(origin HOME)),$(HOME),$(HOME_TEAM_DEFAULT)) \
	  --away $(or $(AWAY),$(AWAY_TEAM_DEFAULT)) --matches $(MATCHES) --half-seconds $(HALF_SECONDS) \
	  --field $(FIELD) --seed $(SEED) $(if $(filter command line,$(origin TRACKER)),--tracker $(TRACKER),) \
	  $(if $(JOBS),--jobs $(JOBS),) $(if $(SCHEDULER),--scheduler $(SCHEDULER),) \
	  $(if $(OUT),--out $(OUT),) $(if $(RESUME),--resume,)
endif

# Train a robot (TASK=score, STEPS, WORKERS, SEED, OUT, RESUME=1) with Stable-Baselines3: runs/<task>-<time>/ holds
# the policy file, checkpoints, TensorBoard logs and the learning curve. Its first use installs
# requirements-train.txt (PyTorch's CPU build, Stable-Baselines3, TensorBoard) into .venv: scripts/setup_train.sh.
train: setup
	@bash scripts/setup_train.sh
	@$(ROS) python scripts/train.py --task $(TASK) --steps $(STEPS) --seed $(SEED) \
	  $(if $(WORKERS),--workers $(WORKERS),) $(if $(OUT),--out $(OUT),) $(if $(RESUME),--resume,)

# The integration tests one at a time (each starts its own roscore and real-time nodes) and, beside them at a
# lower priority, the lint and the unit tests on every core (pytest-xdist, a test file per worker):
# scripts/run_tests.sh. `make lint` alone answers in under a minute.
test: setup
	@$(ROS) bash scripts/run_tests.sh

unit: setup
	@bash scripts/setup_train.sh
	@$(ROS) python -m pytest -m "not integration" -n auto --dist loadfile

integration: setup
	@$(ROS) python -m pytest -m integration

bench: setup
	@$(ROS) python scripts/bench_sim.py --out bench/results
	@$(ROS) python scripts/bench_tracking.py --out bench/results
	@$(ROS) python scripts/bench_match.py --out bench/results
	@$(ROS) python scripts/bench_lockstep.py --out bench/results
	@$(ROS) python scripts/bench_vision.py --out bench/results
	@$(ROS) python scripts/bench_front_vision.py --out bench/results
	@$(ROS) python scripts/bench_kinect_ball.py --out bench/results
	@$(ROS) python scripts/bench_goalie.py --out bench/results --label after
	@$(ROS) python scripts/bench_team_link.py --out bench/results
	@$(ROS) python scripts/bench_node_timer.py --out bench/results
	@$(ROS) python scripts/bench_hwcontrol.py --out bench/results
	@$(ROS) python scripts/bench_viewer.py --out bench/results
	@$(ROS) python scripts/bench_hostile.py --out bench/results
	@bash scripts/setup_train.sh
	@$(ROS) python scripts/bench_train.py --out bench/results $(if $(RUN),--run $(RUN),)

# Lockstep against ROS on seeds 0..SEEDS-1, matches of 2 x HALF_SECONDS (the ROS ones at real time, on every core:
# long, so not in bench): bench/results/faithfulness.{json,png}.
bench-faithfulness: setup
	@$(ROS) python scripts/bench_faithfulness.py --seeds $(SEEDS) --half-seconds $(HALF_SECONDS) --out bench/results

# The compiled kernels built with AddressSanitizer and UndefinedBehaviorSanitizer (build/sanitize), and the unit
# tests of what they compute run on them: scripts/sanitize.sh.
sanitize: setup
	@$(ROS) bash scripts/sanitize.sh

# A full-length match (2 x 15 min) with every process's RSS and CPU sampled every 10 s: soak/soak.{json,png}.
soak: setup
	@$(ROS) python scripts/soak.py --half-seconds $(SOAK_HALF_SECONDS) --out soak

lint: setup
	@bash scripts/lint.sh

clean:
	rm -rf build devel .catkin_make.log
	rm -f src/*/src/*/_kernels*.so

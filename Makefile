# The two commands: `make match` and `make test`. Each prepares the workspace first.
SHELL := /bin/bash
ROS := source devel/setup.bash &&
HALF_SECONDS ?= 90
TRACKER ?= mpc
FIELD ?= 18x12
DEMO_SECONDS ?= 60
SOAK_HALF_SECONDS ?= 900

.PHONY: setup match demo test unit integration bench soak lint clean

setup:
	@bash scripts/setup.sh

match: setup
	@$(ROS) python scripts/run_match.py --half-seconds $(HALF_SECONDS) --tracker $(TRACKER) --field $(FIELD)

demo: setup
	@$(ROS) python scripts/run_demo.py --sim-seconds $(DEMO_SECONDS)

test: lint
	@$(ROS) python -m pytest

unit: setup
	@$(ROS) python -m pytest -m "not integration"

integration: setup
	@$(ROS) python -m pytest -m integration

bench: setup
	@$(ROS) python scripts/bench_sim.py --out bench/results
	@$(ROS) python scripts/bench_tracking.py --out bench/results
	@$(ROS) python scripts/bench_match.py --out bench/results

# A full-length match (2 x 15 min) with every process's RSS and CPU sampled every 10 s: soak/soak.{json,png}.
soak: setup
	@$(ROS) python scripts/soak.py --half-seconds $(SOAK_HALF_SECONDS) --out soak

lint: setup
	@.venv/bin/ruff check src scripts
	@mypy --python-executable .venv/bin/python

clean:
	rm -rf build devel .catkin_make.log

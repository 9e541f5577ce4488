# The two commands: `make match` and `make test`. Each prepares the workspace first.
SHELL := /bin/bash
ROS := source devel/setup.bash &&
MATCH_SECONDS ?= 60

.PHONY: setup match test unit integration bench lint clean

setup:
	@bash scripts/setup.sh

match: setup
	@$(ROS) python scripts/run_demo.py --sim-seconds $(MATCH_SECONDS)

test: setup
	@$(ROS) python -m pytest

unit: setup
	@$(ROS) python -m pytest -m "not integration"

integration: setup
	@$(ROS) python -m pytest -m integration

bench: setup
	@$(ROS) python scripts/bench_sim.py --out bench/results

lint: setup
	@.venv/bin/ruff check src scripts

clean:
	rm -rf build devel .catkin_make.log

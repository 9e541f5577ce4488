"""The folders a tool writes into unless told otherwise, relative to the folder it runs in (``make`` runs every tool
from the repository: matches land in ``matches/``, benchmarks in ``bench/results/`` there), and the shipped team
YAMLs. The packages' own files are found by ROS's package lookup (``nubot_common.packages``), in a source, devel or
install space alike."""

from pathlib import Path

from nubot_common.packages import shipped_teams

BENCH_RESULTS = Path("bench") / "results"
MATCHES = Path("matches")
SOAK = Path("soak")
TEAMS = shipped_teams()  # the shipped team YAMLs

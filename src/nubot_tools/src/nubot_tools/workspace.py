"""Where the workspace's own files are: team configurations, and the default folders for matches and benchmarks."""

from pathlib import Path

from nubot_common.packages import shipped_teams

WORKSPACE = Path(__file__).resolve().parents[4]  # the catkin workspace (the repository) this module lives in
TEAMS = shipped_teams()  # the shipped team YAMLs

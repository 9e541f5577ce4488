"""Where the workspace's own files are: team configurations, and the default folders for matches and benchmarks."""

from pathlib import Path

WORKSPACE = Path(__file__).resolve().parents[4]  # the catkin workspace (the repository) this module lives in
TEAMS = WORKSPACE / "src" / "nubot_control" / "config" / "teams"  # the shipped team YAMLs

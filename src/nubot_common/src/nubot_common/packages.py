"""Where the workspace's packages are: found through ROS's own package lookup (``rospkg``, the ROS_PACKAGE_PATH that
``devel/setup.bash`` sets, as ``rospack find`` finds them), so a source, devel or install space all work."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import rospkg

from nubot_common import NubotCommonError


@cache
def package_path(name: str) -> Path:
    """The folder of the ROS package ``name`` (its package.xml, config/ and launch/)."""
    try:
        return Path(rospkg.RosPack().get_path(name))
    except rospkg.ResourceNotFound:
        raise NubotCommonError(f"no ROS package {name!r} on ROS_PACKAGE_PATH; run 'source devel/setup.bash' (after "
                               f"'make setup', which builds the workspace)") from None


def shipped_teams() -> Path:
    """The folder of the shipped team YAMLs (nubot.yaml, rival.yaml, ...)."""
    return package_path("nubot_control") / "config" / "teams"

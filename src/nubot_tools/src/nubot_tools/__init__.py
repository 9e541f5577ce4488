"""The tools around a match (pure Python; no rospy here, see ``ros`` for the tools that drive a ROS graph).

Rooms: ``bench`` (the benchmarks without ROS, on one ``bench.harness``), ``report`` (``match_report``, the report
from a match bag alone, and ``match_plots``), ``ros`` (the runners of ROS graphs), with ``workspace`` (the
repository's folders for matches and benchmarks). The
statistics of a match (``match_analysis``, ``match_shots``) live in ``nubot_match``, which uses them; the
ROS process groups (``processes``) and launch checks the tests share in ``nubot_common``. Each script in the workspace's
``scripts/`` only calls one of these; the tools that need both the simulator and a robot package
(``front_calibration``, ``kick_measurements``) are this package's nodes (``rosrun nubot_tools ...``).
"""

import matplotlib

matplotlib.use("Agg")  # the tools draw into files, never on a screen (also on a machine with a display)

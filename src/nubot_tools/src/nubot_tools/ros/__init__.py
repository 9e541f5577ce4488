"""Tools that drive a ROS graph from outside, as ``rostopic`` does: the only modules under ``src/`` that use rospy.

Modules: ``match_runner`` (a refereed match with a bag and its report), ``spawner`` (one team into a
running simulator), ``demo_runner`` (the single-robot demo of chapter 6), ``bench_sim``,
``bench_tracking``, ``bench_match`` (the benchmarks of ``make bench``). They start processes with
``nubot_common.processes`` and listen to the graph through rospy; every decision of a match stays in
the pure cores of the robot packages.
"""

"""The benchmarks that run without ROS (``make bench`` runs them through ``scripts/``; their JSON and plots go to
``bench/results``), on one shared harness (``harness``). Those that drive a ROS graph are in ``nubot_tools.ros``."""

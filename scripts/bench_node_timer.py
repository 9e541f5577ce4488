#!/usr/bin/env python3
from nubot_tools.ros.bench_node_timer import main

raise SystemExit(main())

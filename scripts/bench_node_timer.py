#!/usr/bin/env python3
from nubot_tools.bench_node_timer import main

raise SystemExit(main())

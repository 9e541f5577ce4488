#!/usr/bin/env python3
from nubot_tools.ros.bench_sim import main

raise SystemExit(main())

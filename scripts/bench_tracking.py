#!/usr/bin/env python3
from nubot_tools.ros.bench_tracking import main

raise SystemExit(main())

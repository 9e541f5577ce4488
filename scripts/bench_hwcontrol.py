#!/usr/bin/env python3
from nubot_tools.bench_hwcontrol import main

raise SystemExit(main())

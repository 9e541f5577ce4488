#!/usr/bin/env python3
from nubot_tools.ros.bench_viewer import main

raise SystemExit(main())

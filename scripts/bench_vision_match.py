#!/usr/bin/env python3
from nubot_tools.ros.bench_vision_match import main

raise SystemExit(main())

#!/usr/bin/env python3
from nubot_tools.bench_kinect_ball import main

raise SystemExit(main())

#!/usr/bin/env python3
from nubot_tools.bench.kinect_ball import main

raise SystemExit(main())

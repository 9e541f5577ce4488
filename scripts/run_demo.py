#!/usr/bin/env python3
from nubot_tools.ros.demo_runner import main

raise SystemExit(main())

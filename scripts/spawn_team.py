#!/usr/bin/env python3
from nubot_tools.ros.spawner import main

raise SystemExit(main())

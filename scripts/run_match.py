#!/usr/bin/env python3
from nubot_tools.ros.match_runner import main

raise SystemExit(main())

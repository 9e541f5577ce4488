#!/usr/bin/env python3
from nubot_tools.ros.soak import main

raise SystemExit(main())

#!/usr/bin/env python3
from nubot_tools.bench.hwcontrol import main

raise SystemExit(main())

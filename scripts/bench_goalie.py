#!/usr/bin/env python3
from nubot_tools.bench.goalie import main

raise SystemExit(main())

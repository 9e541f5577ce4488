#!/usr/bin/env python3
from nubot_tools.bench_goalie import main

raise SystemExit(main())

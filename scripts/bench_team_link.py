#!/usr/bin/env python3
from nubot_tools.bench.team_link import main

raise SystemExit(main())

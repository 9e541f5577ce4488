#!/usr/bin/env python3
from nubot_tools.report.match_report import main

raise SystemExit(main())

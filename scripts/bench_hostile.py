#!/usr/bin/env python3
from nubot_tools.bench.hostile import main

raise SystemExit(main())

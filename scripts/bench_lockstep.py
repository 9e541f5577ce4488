#!/usr/bin/env python3
from nubot_tools.bench_lockstep import main

raise SystemExit(main())

#!/usr/bin/env python3
from nubot_tools.bench.lockstep import main

raise SystemExit(main())

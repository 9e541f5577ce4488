#!/usr/bin/env python3
from nubot_tools.bench_vision import main

raise SystemExit(main())

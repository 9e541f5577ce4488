#!/usr/bin/env python3
from nubot_tools.bench_front_vision import main

raise SystemExit(main())

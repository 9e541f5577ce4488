#!/usr/bin/env python3
from nubot_tools.bench.front_vision import main

raise SystemExit(main())

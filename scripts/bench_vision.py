#!/usr/bin/env python3
from nubot_tools.bench.vision import main

raise SystemExit(main())

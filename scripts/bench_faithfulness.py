#!/usr/bin/env python3
from nubot_tools.ros.bench_faithfulness import main

raise SystemExit(main())

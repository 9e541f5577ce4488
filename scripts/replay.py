#!/usr/bin/env python3
from nubot_tools.replay import main

raise SystemExit(main())

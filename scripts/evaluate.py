#!/usr/bin/env python3
from nubot_match.evaluate import main

raise SystemExit(main())

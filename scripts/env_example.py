#!/usr/bin/env python3
from nubot_match.envs.example import main

raise SystemExit(main())

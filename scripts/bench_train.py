#!/usr/bin/env python3
from nubot_tools.bench.train import main

if __name__ == "__main__":  # the environments' worker processes import this file again
    raise SystemExit(main())

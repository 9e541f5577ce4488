#!/usr/bin/env python3
from nubot_match.evaluate import main

if __name__ == "__main__":  # a policy's evaluation starts its workers with forkserver, which imports this file again
    raise SystemExit(main())

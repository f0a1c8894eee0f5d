"""`python -m turtle_traj.cli`: the same as `turtle-traj`."""

import sys

from turtle_traj.cli.main import main

sys.exit(main())

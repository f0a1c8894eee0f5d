"""`python -m turtle_traj`: the trajectory node (see `turtle_traj.apps.node`)."""

import sys

from turtle_traj.apps.node import main

sys.exit(main())

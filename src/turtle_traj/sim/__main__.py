"""`python -m turtle_traj.sim`: the simulator program. Its composition lives in
`turtle_traj.apps.sim` with every other program; this is only its name."""

import sys

from turtle_traj.apps.sim import main

sys.exit(main())

"""`python -m turtle_traj.base`: the physics base program. Its composition lives in
`turtle_traj.apps.base` with every other program; this is only its name."""

import sys

from turtle_traj.apps.base import main

sys.exit(main())

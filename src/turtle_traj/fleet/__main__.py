"""`python -m turtle_traj.fleet`: the fleet coordinator program. Its composition lives in
`turtle_traj.apps.fleet` with every other program; this is only its name."""

import sys

from turtle_traj.apps.fleet import main

sys.exit(main())

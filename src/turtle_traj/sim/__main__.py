import sys

from turtle_traj.sim.main import main

sys.exit(main())

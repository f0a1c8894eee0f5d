import sys

from turtle_traj.node.main import main

sys.exit(main())

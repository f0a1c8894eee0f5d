"""The command line: turtle-traj, its menu, and turtlesim's keyboard teleop."""

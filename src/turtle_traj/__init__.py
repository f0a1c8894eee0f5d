"""turtle_traj: closed-loop turtle trajectories for ROS 2 Jazzy, with its own turtlesim."""

__version__ = '0.1.0'

"""The simulator: a pure-Python, wire-compatible turtlesim that knows no trajectories."""

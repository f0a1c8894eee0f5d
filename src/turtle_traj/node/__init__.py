"""The trajectory node: one service per trajectory, the draw action, timer-driven control."""

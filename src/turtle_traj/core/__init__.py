"""Pure Python, never rclpy: turtlesim's numbers, geometry, control, parameters, planning."""

"""A pure-Python turtlesim: physics core, canvas, ROS node and program."""

"""The trajectory node's ROS interface: service and action names, types and requests."""

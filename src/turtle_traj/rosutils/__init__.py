"""Small ROS utilities every program shares: QoS, interfaces by name, running nodes."""

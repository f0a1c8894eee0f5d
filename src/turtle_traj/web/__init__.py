"""The simulator's live view in a browser: server, ROS bridge, messages and the page."""

"""Testing nodes with pytest: turtle_traj's pytest plugin and what its tests check with.

- `plugin`: the fixtures (`turtle_system`, `turtle_sim`, `rclpy_context`, `ros_domain_id`),
  found by pytest through the `pytest11` entry point;
- `geometry`: independent geometry for checking poses and drawings (distances to a polyline,
  the strokes a path draws, the ink on a canvas);
- `pose_log`: the turtle's poses as its own host sees them, from a separate process;
- `pure_loop`, `starved`: the node's control loop on the simulator's physics, without ROS, on a
  perfect executor or on one that starves it;
- `processes`, `two_hosts`, `browser`: our programs as processes, two hosts in network
  namespaces, a headless chromium.
"""

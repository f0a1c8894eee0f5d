"""A differential-drive base with real physics (MuJoCo): the model, its motors, wheel
odometry, and the ROS node that makes it a ROS 2 mobile base. It knows no trajectories."""

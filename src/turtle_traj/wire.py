"""turtlesim's topic QoS as an rclpy profile, for the simulator's node and the controller's
(the numbers are in turtlesim_contract)."""

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from turtle_traj.turtlesim_contract import TOPIC_QOS_DEPTH

# turtlesim's per-turtle topic QoS (qos.hpp in turtlesim 1.8).
TURTLE_TOPIC_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=TOPIC_QOS_DEPTH, reliability=ReliabilityPolicy.RELIABLE)

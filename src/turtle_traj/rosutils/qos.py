"""turtlesim's topic QoS as an rclpy profile, for the simulator's node and the controller's
(the numbers are in turtlesim_contract)."""

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from turtle_traj.core.turtlesim_contract import STEP_S, TOPIC_QOS_DEPTH

# turtlesim's per-turtle topic QoS (qos.hpp in turtlesim 1.8).
TURTLE_TOPIC_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=TOPIC_QOS_DEPTH, reliability=ReliabilityPolicy.RELIABLE)

# What the controller keeps of the pose topic: 2 s of poses, best effort. A reader's history and
# reliability are its own (it matches turtlesim's reliable publisher all the same): a node that
# falls behind, starved or busy, then reads every pose it missed, in order, instead of the last 7
# of them and a turtle that seems to have jumped. Best effort: on a lossy link a lost pose is
# not resent, so the poses after it are not held back until its repair (75 ms at 5% loss, up to
# 150 ms at 20%, measured across two hosts); the controller steers from the newest.
POSE_READER_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=round(2.0 / STEP_S),
    reliability=ReliabilityPolicy.BEST_EFFORT)

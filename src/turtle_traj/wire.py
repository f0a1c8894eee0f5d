"""What the simulator and the controller agree on over the wire, as turtlesim defines it.

Small on purpose: the trajectory node takes its topic QoS and the world's size from here, not
from the simulator's node (which would load the whole simulator into the controller).
"""

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from turtle_traj.sim.physics import SPAWN_XY_M, STEP_S, WORLD_SIZE_M

__all__ = ['SPAWN_XY_M', 'STEP_S', 'TURTLE_TOPIC_QOS', 'WORLD_SIZE_M']

# turtlesim's per-turtle topic QoS (qos.hpp in turtlesim 1.8).
TURTLE_TOPIC_QOS = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=7, reliability=ReliabilityPolicy.RELIABLE)

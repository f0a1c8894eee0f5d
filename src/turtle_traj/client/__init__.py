"""Clients of the trajectory node: TrajClient for scripts, the live view's panel."""

from turtle_traj.client.traj_client import GoalRejected, Interrupted, TrajClient, TrajClientError

__all__ = ['GoalRejected', 'Interrupted', 'TrajClient', 'TrajClientError']

"""Requests to checked plans: the limits of a request, each kind's sketch, the planner."""

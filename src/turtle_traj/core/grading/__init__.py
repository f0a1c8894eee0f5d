"""Grading a lab: task files, and drawings judged from what the simulator recorded."""

"""Grading a turtlesim lab: students' programs run isolated against the grader's simulator
(`sandbox`, `room`, `submission`), judged from its record (`grader`), reported (`reports`)."""

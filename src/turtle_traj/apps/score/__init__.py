"""`turtle-traj score`: controllers ranked on the same courses (see `score.main`)."""

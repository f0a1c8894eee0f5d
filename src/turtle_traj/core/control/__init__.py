"""Control: a plan and poses in, velocity commands out (follower, supervisor, loop)."""

"""One sketch function per kind of trajectory (see `planning`)."""

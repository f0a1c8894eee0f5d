"""One sketch function per kind of trajectory: a request to a path."""

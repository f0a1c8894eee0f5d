"""Every program: the compositions of nodes into one process, in one place."""

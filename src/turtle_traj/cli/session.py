"""Many `turtle-traj` calls in one process, for tests that make dozens (the two-host tests).

    python -m turtle_traj.cli.session

Each line on stdin is a call's arguments as a JSON list (`["draw", "square", "--size", "0.5"]`);
each line on stdout its answer, as JSON: `{"returncode": 0, "stdout": "...", "stderr": "..."}`.
A call runs the command line's own `main`, so it says what `turtle-traj ARGS` says. What a new
process would redo at each call is done once: Python's start and imports, rclpy's start, and the
discovery of the node (a node of the session's own keeps its DDS participant, and what it
learnt, for the session's life).
"""

from __future__ import annotations

import contextlib
import io
import json
import sys


def answer(argv: list[str]) -> dict[str, object]:
    """Run `turtle-traj ARGV` here: its exit code and what it printed."""
    from turtle_traj.cli.main import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exit_:  # a usage error
            code = exit_.code if isinstance(exit_.code, int) else 2
    return {'returncode': code, 'stdout': out.getvalue(), 'stderr': err.getvalue()}


def main() -> int:
    import rclpy

    from turtle_traj.rosutils.runtime import process_context
    context, _ = process_context()
    keeper = rclpy.create_node('turtle_traj_cli_session', context=context)
    try:
        for line in sys.stdin:
            print(json.dumps(answer(json.loads(line))), flush=True)
    finally:
        keeper.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())

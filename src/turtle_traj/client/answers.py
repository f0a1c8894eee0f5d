"""Answers to requests that DDS may lose: a request sent again while unanswered.

Why: a service answers as soon as it has a request, but rmw_fastrtps drops the answer when the
service has not yet matched the new client's reply reader ("failed to send response
(timeout): client will not receive response"; it waits 100 ms, ros2/rmw_fastrtps#467, and rcl
leaves the timeout unhandled, ros2/ros2#1017). The client sees the service ready as soon as it
has matched the service's endpoints, so its first request can race the other direction's
discovery. Seen once in 200 parameter reads with both cores busy, and on a reset; pinned by
tests/test_client.py (a first answer dropped). rclpy has no retry of its own for a call.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from rclpy.executors import Executor
from rclpy.task import Future

ANSWER_WAIT_S = 2.0  # a request not answered within this is sent again
REQUEST_ATTEMPTS = 3


class TrajClientError(RuntimeError):
    """The call could not be made or did not finish; the message says why."""


def first_answer(executor: Executor, send: Callable[[], Future], what: str,
                 sent: list[Future] | None = None, *,
                 timeout_s: float = REQUEST_ATTEMPTS * ANSWER_WAIT_S):
    """The first answer to a request, sent again (up to REQUEST_ATTEMPTS times, every
    ANSWER_WAIT_S) while none comes, spinning `executor` meanwhile. Only for requests that are
    harmless when the first got through too: the same goal id, a cancel, a result request, a
    parameter read, the same value set again, reset, stop.

    :param sent: where the futures of the requests sent are kept, for the caller.
    :param timeout_s: how long to wait for an answer in all, from the first request.
    :raises TrajClientError: no answer within `timeout_s`.
    """
    sent = [] if sent is None else sent
    start, sent_at = time.monotonic(), -math.inf
    while True:
        for future in sent:
            if future.done():
                return future.result()
        now = time.monotonic()
        if sent and now - start >= timeout_s:
            raise TrajClientError(f'{what} did not answer within {timeout_s:g} s '
                                  f'({len(sent)} requests)')
        if len(sent) < REQUEST_ATTEMPTS and now - sent_at >= ANSWER_WAIT_S:
            sent.append(send())
            sent_at = now
        executor.spin_once(timeout_sec=0.05)

"""Room slots (`grading.slots`): no more rooms at once than there are slots, whoever holds
them; a slot comes free when its holder lets go or dies."""

import subprocess
import sys
import threading
import time

from turtle_traj.grading.slots import room_slot


def test_a_room_waits_for_a_slot_and_takes_the_one_freed(tmp_path):
    first, second = room_slot(2, tmp_path), room_slot(2, tmp_path)
    assert (first.__enter__(), second.__enter__()) == (0, 1)
    taken = []
    waiting = threading.Thread(target=lambda: taken.append(room_slot(2, tmp_path).__enter__()))
    waiting.start()
    waiting.join(timeout=0.3)
    assert waiting.is_alive() and not taken  # both slots held
    second.__exit__(None, None, None)
    waiting.join(timeout=5.0)
    assert taken == [1]
    first.__exit__(None, None, None)


def test_a_slot_held_by_a_process_that_is_killed_comes_free(tmp_path):
    holder = subprocess.Popen([sys.executable, '-c', (
        'import sys, time\n'
        'from turtle_traj.grading.slots import room_slot\n'
        f'with room_slot(1, __import__("pathlib").Path({str(tmp_path)!r})):\n'
        '    print("held", flush=True)\n'
        '    time.sleep(60)\n')], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == 'held'
        taken = []
        waiting = threading.Thread(target=lambda: taken.append(
            room_slot(1, tmp_path).__enter__()))
        waiting.start()
        time.sleep(0.2)
        assert not taken
        holder.kill()
        waiting.join(timeout=5.0)
        assert taken == [0]
    finally:
        holder.kill()
        holder.wait()

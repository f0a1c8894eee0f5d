"""The ready-made labs beyond the square, and one run watched live.

The circle, spiral, go-to-goal and letter labs grade their samples as each lab's
expected_grades.yaml says (graded at once, as four classes); `grade --watch` serves one run's
live view on 127.0.0.1, watch only, and the run gets the grade it gets unwatched. (The square
lab's class and its hostile samples: tests/test_grading_class.py.)
"""

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
import yaml

from turtle_traj.apps.grade import load_task
from turtle_traj.core.turtlesim_contract import PIXELS_PER_METER
from turtle_traj.grading.grader import grade_class

LABS = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj' / 'labs'
LAB = LABS / 'square'
OTHER_LABS = ('circle', 'spiral', 'go_to_goal', 'letter')


@pytest.mark.system
@pytest.mark.timeout(300)
def test_every_other_lab_gives_its_samples_their_grades(tmp_path):
    """The circle, spiral, go-to-goal and letter labs, graded at once: each sample gets the
    grade its lab's expected_grades.yaml gives it."""
    def graded(lab: str) -> dict:
        task = load_task(LABS / lab / 'task.yaml')
        return {result.name: result for result in grade_class(
            task, LABS / lab / 'samples', tmp_path / lab)}

    with ThreadPoolExecutor(len(OTHER_LABS)) as pool:
        labs = dict(zip(OTHER_LABS, pool.map(graded, OTHER_LABS), strict=True))
    for lab, results in labs.items():
        expected = yaml.safe_load((LABS / lab / 'samples' / 'expected_grades.yaml').read_text())
        got = {name: result.score for name, result in results.items()}
        assert got == expected, (lab, {name: [check.message for check in result.checks]
                                       for name, result in results.items()})
    goal = {check.name: check for check in labs['go_to_goal']['right'].checks}['goal']
    assert goal.message.startswith('the turtle ended 0.0') and '(8.00, 3.00)' in goal.message
    teleported = labs['go_to_goal']['teleports'].checks
    assert {check.message for check in teleported} == {'the turtle never moved'}
    mirrored = {check.name: check for check in labs['letter']['mirrored'].checks}['shape']
    assert 'beyond the tolerance' in mirrored.message


@pytest.mark.system
@pytest.mark.timeout(200)
def test_one_run_is_watched_live_and_the_view_cannot_drive(tmp_path):
    """`grade --watch`: while the run goes on, the page on 127.0.0.1 shows the square being
    drawn; an arrow key pressed there is refused; the grade is the one it gets unwatched."""
    import threading

    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys

    from turtle_traj.grading.grader import watch_one
    from turtle_traj.testing.browser import chromium, free_port, page_canvas, wait_for

    task, urls, graded = load_task(LAB / 'task.yaml'), [], {}
    runner = threading.Thread(target=lambda: graded.update(result=watch_one(
        task, LAB / 'samples', tmp_path, 'right', free_port(), urls.append)))
    runner.start()
    try:
        wait_for(lambda: urls, what='the live view address')
        assert urls[0].startswith('http://127.0.0.1:')
        with chromium() as driver:
            driver.get(urls[0])

            def trail() -> int:  # the pen's colour on the canvas, in pixels
                return int(np.all(page_canvas(driver) == (179, 184, 255), axis=2).sum())

            wait_for(lambda: trail() > 2 * PIXELS_PER_METER, timeout_s=60.0,
                     what='the first side drawn on the page')
            driver.execute_script('document.getElementById("view").focus()')
            ActionChains(driver).send_keys(Keys.ARROW_UP).perform()
            wait_for(lambda: 'only watches' in driver.find_element('id', 'error').text,
                     what='the key refused')
            wait_for(lambda: trail() > 7 * PIXELS_PER_METER, timeout_s=60.0,
                     what='the square drawn on the page')
    finally:
        runner.join(timeout=120)
    assert graded['result'].score == 11

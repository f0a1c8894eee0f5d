"""A real browser for the live view's tests: Debian's chromium through its chromedriver.

Missing, the browser tests are skipped with what is missing named; under CI (CI=true) a missing
browser fails them instead.
"""

from __future__ import annotations

import base64
import io
import os
import shutil
import socket
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np
import pytest
from PIL import Image

CHROMIUM = '/usr/bin/chromium'
CHROMEDRIVER = '/usr/bin/chromedriver'


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def browser_missing() -> str | None:
    """What is missing for the browser tests, or None."""
    missing = [path for path in (CHROMIUM, CHROMEDRIVER) if not shutil.which(path)]
    try:
        import selenium  # noqa: F401
    except ImportError:
        missing.append('selenium (make setup installs it)')
    if not missing:
        return None
    return (f'{" and ".join(missing)} missing: apt-get install chromium chromium-driver '
            '(Debian) for the browser tests')


@contextmanager
def chromium() -> Iterator[object]:
    """A headless chromium, closed afterwards (skips or fails when it is not installed)."""
    missing = browser_missing()
    if missing is not None:
        if os.environ.get('CI'):
            pytest.fail(f'CI runs the browser tests: {missing}')
        pytest.skip(missing)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    # Its own temporary folder for the profile and what chromium leaves beside it (a
    # `org.chromium.Chromium.*` folder in $TMPDIR per browser, which a quit does not remove:
    # three a suite, 216 in /tmp here after a day of runs), removed with the browser.
    with tempfile.TemporaryDirectory(prefix='turtle_traj-chromium-',
                                     ignore_cleanup_errors=True) as private:
        options = webdriver.ChromeOptions()
        options.binary_location = CHROMIUM
        for argument in ('--headless=new', '--no-sandbox', '--disable-gpu',
                         '--disable-dev-shm-usage', '--window-size=1100,720',
                         '--force-device-scale-factor=1', f'--user-data-dir={private}/profile'):
            options.add_argument(argument)
        service = Service(CHROMEDRIVER, env={**os.environ, 'TMPDIR': private})
        driver = webdriver.Chrome(service=service, options=options)
        try:
            yield driver
        finally:
            driver.quit()


def wait_for(condition: Callable[[], object], timeout_s: float = 20.0,
             what: str = 'condition') -> object:
    """Poll `condition` until it returns something true; that value (AssertionError after
    `timeout_s`)."""
    deadline = time.monotonic() + timeout_s
    while not (value := condition()):
        assert time.monotonic() < deadline, f'{what} not met within {timeout_s:g} s'
        time.sleep(0.05)
    return value


def page_canvas(driver) -> np.ndarray:
    """The page's canvas (background and trails, no turtles) as an RGB array."""
    url = driver.execute_script('return window.turtleTraj.viewPNG()')
    png = base64.b64decode(url.split(',', 1)[1])
    return np.asarray(Image.open(io.BytesIO(png)).convert('RGB'))

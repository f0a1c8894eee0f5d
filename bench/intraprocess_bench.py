"""Fast DDS's intraprocess delivery on (its default, ours) and off, side by side.

With it on, a message published to a subscriber of the same participant is handed over inside
`publish()`; lock-step relies on that (tests/test_lockstep_contract.py). With it off, it goes
through the transport like any other. Each figure alternates a profile file that is our
fastdds.xml as it is with one that adds `<intraprocess_delivery>OFF</intraprocess_delivery>`:
the lock-step real-time factor (bench/speed_bench.py's, one turtle drawing a circle), and the
lock-step tests' outcome.

Run: .venv/bin/python bench/intraprocess_bench.py [--rounds N]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from isolation import isolate

ROOT = Path(__file__).resolve().parents[1]
OURS = ROOT / 'src' / 'turtle_traj' / 'rosutils' / 'fastdds.xml'
OFF = '<library_settings><intraprocess_delivery>OFF</intraprocess_delivery></library_settings>'


def _profile_off() -> Path:
    text = OURS.read_text()
    opening = text.index('>', text.index('<profiles')) + 1
    path = Path(tempfile.mkdtemp(prefix='turtle_traj_intraprocess_')) / 'off.xml'
    path.write_text(text[:opening] + '\n  ' + OFF + text[opening:])
    return path


def _run(profile: Path, *command: str, timeout_s: float) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, *command], cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, 'FASTRTPS_DEFAULT_PROFILES_FILE': str(profile)},
                          timeout=timeout_s)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rounds', type=int, default=3)
    options = parser.parse_args()
    isolate('speed')
    profiles = {'on': OURS, 'off': _profile_off()}
    factors: dict[str, list[float]] = {'on': [], 'off': []}
    for _ in range(options.rounds):
        for name, profile in profiles.items():
            done = _run(profile, 'bench/speed_bench.py', '--measure', 'rtf1', timeout_s=900)
            factors[name].append(json.loads(done.stdout.strip().splitlines()[-1])['factor'])
    print(f'Fast DDS intraprocess delivery on / off, median of {options.rounds}, alternating')
    for name in profiles:
        print(f'  {name:3s}: lock-step real-time factor {statistics.median(factors[name]):7.2f}x')
    for name, profile in profiles.items():
        tests = _run(profile, '-m', 'pytest', '-q', '-p', 'no:cacheprovider', '--timeout=60',
                     'tests/test_lockstep_contract.py', 'tests/test_lockstep.py',
                     timeout_s=1800)
        print(f'  {name:3s}: lock-step tests: {tests.stdout.strip().splitlines()[-1]}')


if __name__ == '__main__':
    main()

"""Two hosts on one machine: two network namespaces joined by a veth pair, for the two-machine
recipe (docs/tutorials/two-machines.md) and its faults (packet loss with nftables, link cuts),
for testing nodes across hosts (our tests/test_two_hosts.py, bench/network_bench.py). Needs
root.

Everything it makes carries this process's id in its name, and it removes only what it made:
the namespaces (their veth ends and nft tables go with them) on `close`, at exit, or when the
context ends by an error or Ctrl-C. The addresses are its own, inside its namespaces only.
"""

from __future__ import annotations

import atexit
import json
import math
import os
import re
import select
import shutil
import subprocess
import sys
from pathlib import Path

from turtle_traj.rosutils.fastdds_profile import across_hosts

SUBNET = '10.213.{}.{}'
NFT_TABLE = 'turtle_traj_faults'


def _printed(output: str, pattern: str) -> float:
    found = re.search(pattern, output)
    return float(found.group(1)) if found else math.nan


def reported_deviation_m(output: str) -> float:
    """The maximum deviation a CLI call printed (nan: none)."""
    return _printed(output, r'max deviation ([0-9.]+) m')


def reported_elapsed_s(output: str) -> float:
    """The run's time, by the node's clock, that a CLI call printed (nan: none)."""
    return _printed(output, r'elapsed ([0-9.]+) s')


class TwoHostsUnavailable(RuntimeError):
    """Network namespaces cannot be made here; the message says why."""


def _run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run(args, capture_output=True, text=True, check=check, timeout=10)


def why_unavailable() -> str | None:
    """Why two hosts cannot be made on this machine (None: they can)."""
    if os.geteuid() != 0:
        return 'network namespaces need root'
    for tool in ('ip', 'nft'):
        if shutil.which(tool) is None:
            return f'{tool} is not installed (Debian: apt-get install iproute2 nftables)'
    return None


class CliSession:
    """`turtle-traj` calls made in one process (`turtle_traj.cli.session`), answered as
    `subprocess.run` answers."""

    # the program, and how it is started: its answers on a pipe, its logs nowhere
    ARGV = (sys.executable, '-m', 'turtle_traj.cli.session')
    PIPES = {'stdin': subprocess.PIPE, 'stdout': subprocess.PIPE, 'stderr': subprocess.DEVNULL,
             'text': True}

    def __init__(self, process: subprocess.Popen) -> None:
        self.process = process

    @classmethod
    def start(cls) -> CliSession:
        """A session on this machine (ended by closing its stdin)."""
        return cls(subprocess.Popen(cls.ARGV, **cls.PIPES))

    def call(self, *args: str, timeout_s: float) -> subprocess.CompletedProcess:
        """Run `turtle-traj ARGS` in the session to its end.

        :raises subprocess.TimeoutExpired: no answer within `timeout_s`.
        """
        self.process.stdin.write(json.dumps(args) + '\n')
        self.process.stdin.flush()
        ready, _, _ = select.select([self.process.stdout], [], [], timeout_s)
        line = self.process.stdout.readline() if ready else ''
        if not line:
            raise subprocess.TimeoutExpired(['turtle-traj', *args], timeout_s)
        said = json.loads(line)
        return subprocess.CompletedProcess(['turtle-traj', *args], said['returncode'],
                                           said['stdout'], said['stderr'])


class TwoHosts:
    """Host `a` (10.213.N.1) and host `b` (10.213.N.2) on a veth pair; `run(host, ...)`
    starts a program on one of them."""

    def __init__(self, domain_id: int) -> None:
        if (problem := why_unavailable()) is not None:
            raise TwoHostsUnavailable(problem)
        tag = os.getpid() % 100000
        self.names = {'a': f'tt{tag}a', 'b': f'tt{tag}b'}  # namespace and its link: <= 15
        self.address = {'a': SUBNET.format(tag % 250, 1), 'b': SUBNET.format(tag % 250, 2)}
        self.env = {**across_hosts(os.environ), 'ROS_DOMAIN_ID': str(domain_id),
                    # UDP only, also where our profile is not taken (Fast DDS's shared memory
                    # would carry the data past the link between the hosts)
                    'FASTDDS_BUILTIN_TRANSPORTS': 'UDPv4'}
        self._made: list[str] = []
        self._processes: list[subprocess.Popen] = []
        atexit.register(self.close)
        try:
            self._build()
        except BaseException:
            self.close()
            raise

    def _build(self) -> None:
        for host in 'ab':
            name = self.names[host]
            if name in _run('ip', 'netns', 'list').stdout.split():
                raise TwoHostsUnavailable(f'namespace {name} exists and is not ours')
        for host in 'ab':
            _run('ip', 'netns', 'add', self.names[host])
            self._made.append(self.names[host])
        a, b = self.names['a'], self.names['b']
        _run('ip', 'link', 'add', a, 'netns', a, 'type', 'veth', 'peer', 'name', b, 'netns', b)
        for host in 'ab':
            ns, link = self.names[host], self.names[host]
            _run('ip', '-n', ns, 'addr', 'add', f'{self.address[host]}/24', 'dev', link)
            _run('ip', '-n', ns, 'link', 'set', link, 'up')
            _run('ip', '-n', ns, 'link', 'set', 'lo', 'up')
            _run('ip', '-n', ns, 'route', 'add', '224.0.0.0/4', 'dev', link)

    def command(self, host: str, *args: str) -> list[str]:
        """`args` as run on `host`."""
        return ['ip', 'netns', 'exec', self.names[host], *args]

    def _spawn(self, host: str, *args: str, **kwargs) -> subprocess.Popen:
        """Start `args` on `host`, to be ended by `close`."""
        process = subprocess.Popen(self.command(host, *args), env=self.env, **kwargs)
        self._processes.append(process)
        return process

    def run(self, host: str, *args: str, **kwargs) -> subprocess.Popen:
        """Start `python -m ARGS` on `host` (ended by `close`)."""
        return self._spawn(host, sys.executable, '-m', *args, **kwargs)

    cli = Path(sys.executable).with_name('turtle-traj')

    def log_poses(self, host: str, out: Path) -> subprocess.Popen:
        """Log the turtle's poses and the node's plans on `host` into `out` (`pose_log`):
        on the simulator's host, what the turtle really did, whatever the link lost."""
        return self._spawn(host, sys.executable, '-m', 'turtle_traj.testing.pose_log', str(out),
                           stderr=subprocess.DEVNULL)

    def start(self, host: str, *args: str) -> subprocess.Popen:
        """Start `turtle-traj ARGS` on `host` and leave it running (a trajectory to cut); its
        output, both streams, on its stdout."""
        return self._spawn(host, str(self.cli), *args, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)

    def call(self, host: str, *args: str, timeout_s: float) -> subprocess.CompletedProcess:
        """Run `turtle-traj ARGS` on `host` to its end."""
        return subprocess.run(self.command(host, str(self.cli), *args), env=self.env,
                              capture_output=True, text=True, timeout=timeout_s)

    def session(self, host: str) -> CliSession:
        """A process on `host` that makes `turtle-traj` calls one after another
        (`turtle_traj.cli.session`): each says what its own process would, without starting one."""
        return CliSession(self._spawn(host, *CliSession.ARGV, **CliSession.PIPES))

    def loss(self, percent: int) -> None:
        """Drop `percent` of packets each way (each host's outgoing packets); 0 for none."""
        for host in 'ab':
            ns = self.names[host]
            _run('ip', 'netns', 'exec', ns, 'nft', 'delete', 'table', 'inet', NFT_TABLE,
                 check=False)
            if percent:
                rules = (f'table inet {NFT_TABLE} {{\n chain out {{\n'
                         '  type filter hook output priority 0;\n'
                         f'  oifname "{self.names[host]}" numgen random mod 100 < {percent} '
                         'drop\n }\n}\n')
                subprocess.run(['ip', 'netns', 'exec', ns, 'nft', '-f', '-'], input=rules,
                               text=True, check=True, capture_output=True, timeout=10)

    def link(self, up: bool) -> None:
        """Cut the link between the hosts (False), or restore it (True)."""
        for host in 'ab':
            _run('ip', '-n', self.names[host], 'link', 'set', self.names[host],
                 'up' if up else 'down')

    def close(self) -> None:
        """End the programs started here, then remove the namespaces this object made."""
        while self._processes:
            process = self._processes.pop()
            if process.poll() is None:
                process.kill()
            process.wait(timeout=10)
        while self._made:
            name = self._made.pop()
            for pid in _run('ip', 'netns', 'pids', name, check=False).stdout.split():
                _run('kill', '-9', pid, check=False)
            _run('ip', 'netns', 'del', name, check=False)

    def __enter__(self) -> TwoHosts:
        return self

    def __exit__(self, *_exc) -> None:
        self.close()

"""The subcommands that run a program of their own here (the simulator and node, the
controller server, the score, teleop, bags) rather than ask a running node: each loads what it
needs only when chosen."""

from __future__ import annotations

import argparse

from turtle_traj.sim.options import options_from


def up(_parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps.node import Options, run  # loads the simulator: only here
    return run(Options(sim=options_from(options), base=options.base, nice=options.nice))


def controller_server(_parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps.controller_server import run
    return run(options.params_file, ['turtle-traj'])


def score(_parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps.score.main import run as run_score
    return run_score(options.controller, options.output, options.course,
                     matched=options.matched)


def grade(_parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps.grade import run
    return run(options.task, options.submissions, options.output, options.jobs, options.watch,
               options.port)


def lab(_parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps.grade import copy_lab
    return copy_lab(options.name, options.folder)


def teleop(_parser: argparse.ArgumentParser, _options: argparse.Namespace) -> int:
    from turtle_traj.cli import teleop
    return teleop.main([])


def bags(parser: argparse.ArgumentParser, options: argparse.Namespace) -> int:
    from turtle_traj.apps import bags as programs
    if options.command == 'record':
        turtle = getattr(options, 'turtle', None)  # a fleet's turtle: its namespace's topics
        fleet, node = None, options.node
        if options.turtles:  # the whole fleet's; the limits noted are turtle1's node's
            if options.topics or turtle:
                parser.error('record --turtles records the fleet: no TOPIC, no --turtle')
            from turtle_traj.bags.recorder import fleet_topics
            fleet = fleet_topics(options.turtles)
            node = '/turtle1/turtle_traj' if node == '/turtle_traj' else node
        return programs.record(options.output, options.topics, node,
                               turtle=f"/{turtle.strip('/')}" if turtle else 'turtle1',
                               defaults=fleet)
    if options.command == 'play':
        return programs.play(options.bag, options.topics, options.rate)
    if options.bag is not None and options.last:
        parser.error('plot takes a BAG or --last, not both')
    return programs.plot(options.bag, options.output)


# by subcommand
LOCAL_PROGRAMS = {'up': up, 'controller-server': controller_server, 'score': score,
                  'grade': grade, 'lab': lab,
                  'teleop': teleop, 'record': bags, 'play': bags, 'plot': bags}

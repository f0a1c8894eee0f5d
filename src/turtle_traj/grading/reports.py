"""What a teacher gets back from grading a class: a picture per student (their drawing over the
reference placed as the task allows, each check marked) and a replay of the run, the class
page (`index.html`), a spreadsheet (`grades.csv`), a summary for scripts (`summary.json`, the
exit status) and Gradescope's `results.json` per student.
"""

from __future__ import annotations

import csv
import html
import json
from collections.abc import Sequence
from pathlib import Path

from PIL import Image, ImageDraw

from turtle_traj.core.grading.task import Task
from turtle_traj.core.turtlesim_contract import CANVAS_HEIGHT_M, PIXELS_PER_METER
from turtle_traj.grading.grader import StudentResult
from turtle_traj.grading.replay import write_replay

REFERENCE_RGBA = (40, 220, 90, 110)
DRAWN_RGBA = (255, 255, 255, 255)
PASSED, FAILED = '\u2713', '\u2717'
_BLANK_RGB = (69, 86, 255)  # turtlesim's background, where the run left no canvas


def picture(result: StudentResult, path: Path,
            goal: tuple[float, float] | None = None) -> Path:
    """The run's canvas with the reference placed over it (a green band), the goal (a green
    ring), the pen's strokes on top (white), and each check marked at the top."""
    try:
        with Image.open(result.run_dir / 'canvas.png') as canvas:
            image = canvas.convert('RGBA')
    except OSError:
        image = Image.new('RGBA', (500, 500), (*_BLANK_RGB, 255))
    layer = Image.new('RGBA', image.size, (0, 0, 0, 0))
    draw = ImageDraw.Draw(layer)
    if result.fit is not None:  # a wide band under the drawing, which is drawn again on it
        draw.line([_pixel(x, y) for x, y in result.fit.points], fill=REFERENCE_RGBA, width=9,
                  joint='curve')
    if goal is not None:
        x, y = _pixel(*goal)
        draw.ellipse((x - 8, y - 8, x + 8, y + 8), outline=REFERENCE_RGBA[:3] + (255,), width=3)
    for stroke in result.drawn:
        draw.line([_pixel(x, y) for x, y in stroke], fill=DRAWN_RGBA, width=2)
    top = 4
    for check in result.checks:
        mark = '+' if check.passed else 'x'  # Pillow's default font has no check marks
        text = f'{mark} {check.name} {check.score:g}/{check.max_score:g}'
        colour = (220, 255, 220, 255) if check.passed else (255, 200, 200, 255)
        draw.rectangle((4, top, 8 + 7 * len(text), top + 13), fill=(0, 0, 0, 140))
        draw.text((6, top + 1), text, fill=colour)
        top += 15
    Image.alpha_composite(image, layer).convert('RGB').save(path)
    return path


def _pixel(x_m: float, y_m: float) -> tuple[float, float]:
    return x_m * PIXELS_PER_METER, (CANVAS_HEIGHT_M - y_m) * PIXELS_PER_METER


def gradescope(result: StudentResult) -> dict:
    """Gradescope's autograder results: the score, and a test per check."""
    return {'score': result.score, 'output': result.ended,
            'tests': [{'name': check.name, 'score': check.score, 'max_score': check.max_score,
                       'output': check.message} for check in result.checks]}


def summary(task: Task, results: Sequence[StudentResult]) -> dict:
    """Every student's score and checks, for scripts (a GitHub Classroom workflow)."""
    return {'task': task.name, 'max_score': task.max_score,
            'students': [{'name': result.name, 'score': result.score, 'ended': result.ended,
                          'checks': [{'name': check.name, 'score': check.score,
                                      'max_score': check.max_score, 'message': check.message}
                                     for check in result.checks]}
                         for result in results]}


def exit_status(results: Sequence[StudentResult]) -> int:
    """0 when every submission got full marks, 1 when one lost points."""
    return 0 if all(result.score >= result.max_score for result in results) else 1


def write_reports(task: Task, results: Sequence[StudentResult], out: Path) -> Path:
    """Write the pictures, Gradescope's results, `grades.csv`, `summary.json` and the class
    page into `out`; returns the class page's path."""
    for result in results:
        picture(result, result.run_dir / 'picture.png', task.expected.goal)
        write_replay(result, result.run_dir / 'replay.html')
        (result.run_dir / 'results.json').write_text(json.dumps(gradescope(result), indent=1))
    with (out / 'grades.csv').open('w', newline='', encoding='utf-8') as file:
        writer = csv.writer(file)
        writer.writerow(['student', 'score', 'max_score', *task.points, 'ended'])
        for result in results:
            writer.writerow([result.name, f'{result.score:g}', f'{result.max_score:g}',
                             *(f'{check.score:g}' for check in result.checks), result.ended])
    (out / 'summary.json').write_text(json.dumps(summary(task, results), indent=1))
    page = out / 'index.html'
    page.write_text(class_page(task, results, out.resolve()), encoding='utf-8')
    return page


def class_page(task: Task, results: Sequence[StudentResult], out: Path) -> str:
    """The class page: a card per student with the picture, the checks and the run's end."""
    cards = []
    for result in results:
        checks = ''.join(
            f'<li class="{"pass" if check.passed else "fail"}">'
            f'{PASSED if check.passed else FAILED} <b>{html.escape(check.name)}</b> '
            f'{check.score:g}/{check.max_score:g}: {html.escape(check.message)}</li>'
            for check in result.checks)
        image = (result.run_dir / 'picture.png').relative_to(out).as_posix()
        log = (f'<details><summary>output</summary><pre>{html.escape(result.log)}</pre>'
               '</details>' if result.log.strip() else '')
        if result.peak:  # what the program took of its limits, at most
            log += (f"<p>at most {result.peak.get('tasks', 0)} tasks and "
                    f"{result.peak.get('memory_mb', 0):.0f} MB at once</p>")
        replay = result.run_dir / 'replay.html'
        if replay.exists():
            link = html.escape(replay.relative_to(out).as_posix())
            log += f'<p><a href="{link}">replay the run</a></p>'
        cards.append(
            f'<section class="card" id="{html.escape(result.name)}">'
            f'<h2>{html.escape(result.name)} <span>{result.score:g} / {result.max_score:g}'
            f'</span></h2><img src="{html.escape(image)}" alt="the drawing of '
            f'{html.escape(result.name)} over the reference" width="320" height="320">'
            f'<ul>{checks}</ul><p>{html.escape(result.ended)}</p>{log}</section>')
    scores = [result.score for result in results]
    mean = sum(scores) / len(scores) if scores else 0.0
    return (f'<!doctype html><html lang="en"><head><meta charset="utf-8">'
            f'<title>{html.escape(task.name)}: grades</title><style>{_STYLE}</style></head>'
            f'<body><h1>{html.escape(task.name)}</h1><p>{len(results)} submissions, mean '
            f'{mean:.1f} of {task.max_score:g}; the reference is the green band, the '
            f'drawing the white line on it. <a href="grades.csv">grades.csv</a> · '
            f'<a href="summary.json">summary.json</a></p>'
            f'<main>{"".join(cards)}</main></body></html>')


_STYLE = ('body{font-family:sans-serif;margin:1em}main{display:flex;flex-wrap:wrap;gap:1em}'
          '.card{border:1px solid #ccc;border-radius:6px;padding:.5em;width:340px}'
          '.card h2{font-size:1.1em;display:flex;justify-content:space-between;margin:.2em 0}'
          '.pass{color:#15652b}.fail{color:#a11}ul{padding-left:1em;font-size:.85em}'
          'pre{white-space:pre-wrap;font-size:.75em;max-height:12em;overflow:auto}')

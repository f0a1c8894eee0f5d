"""A run replayed in the browser, from the simulator's own record: `replay.html`, one
self-contained page (no server, no network) that draws the turtle and its pen over time, with
the reference placed as the judge placed it, a play button and a time slider. For the student
who asks why: what the simulator saw, step by step, beside each check's sentence.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

from turtle_traj.core.turtlesim_contract import CANVAS_HEIGHT_M, CANVAS_SIZE_PX, PIXELS_PER_METER
from turtle_traj.grading.grader import StudentResult

FRAME_S = 0.05  # the poses kept: one every this long


def replay_data(record: dict, result: StudentResult, turtle: str = 'turtle1') -> dict:
    """What the page draws, in canvas pixels: poses (t, x, y, theta), the pen's segments
    (t, x0, y0, x1, y1), the reference, the calls (t, name) and the checks."""
    poses, last = [], -FRAME_S
    for time_s, x, y, theta, *_speeds in record['poses'].get(turtle, []):
        if time_s - last >= FRAME_S:
            poses.append([round(time_s, 3), *_pixel(x, y), round(theta, 4)])
            last = time_s
    segments = [[round(time_s, 3), *_pixel(x0, y0), *_pixel(x1, y1)]
                for time_s, x0, y0, x1, y1 in record['segments']]
    reference = [_pixel(x, y) for x, y in result.fit.points] if result.fit is not None else []
    return {'poses': poses, 'segments': segments, 'reference': reference,
            'calls': [[round(time_s, 2), name] for time_s, name, _turtle in record['calls']],
            'checks': [[check.passed, f'{check.name} {check.score:g}/{check.max_score:g}: '
                        f'{check.message}'] for check in result.checks]}


def write_replay(result: StudentResult, path: Path) -> Path | None:
    """Write the replay page of `result`'s run, if the simulator left a record."""
    try:
        record = json.loads((result.run_dir / 'record.json').read_text())
    except (OSError, ValueError):
        return None
    data = json.dumps(replay_data(record, result)).replace('</', '<\\/')
    path.write_text(_PAGE.replace('{title}', html.escape(result.name))
                    .replace('{size}', str(CANVAS_SIZE_PX)).replace('{data}', data),
                    encoding='utf-8')
    return path


def _pixel(x_m: float, y_m: float) -> list[float]:
    return [round(x_m * PIXELS_PER_METER, 1), round((CANVAS_HEIGHT_M - y_m) * PIXELS_PER_METER, 1)]


_PAGE = '''<!doctype html><html lang="en"><head><meta charset="utf-8">
<title>{title}: replay</title><style>body{font-family:sans-serif;margin:1em}
canvas{background:#4556ff}.pass{color:#15652b}.fail{color:#a11}</style></head><body>
<h1>{title}: the run as the simulator saw it</h1>
<canvas id="view" width="{size}" height="{size}"></canvas>
<p><button id="play">play</button> <input id="time" type="range" min="0" step="0.05"
style="width:400px"> <span id="clock"></span></p><p id="calls"></p><ul id="checks"></ul>
<script>
const run = {data};
const view = document.getElementById('view'), pen = view.getContext('2d');
const slider = document.getElementById('time'), clock = document.getElementById('clock');
const end = run.poses.length ? run.poses[run.poses.length - 1][0] : 0;
slider.max = end;
function draw(t) {
  pen.clearRect(0, 0, view.width, view.height);
  pen.strokeStyle = 'rgba(40,220,90,0.45)'; pen.lineWidth = 9; pen.beginPath();
  run.reference.forEach(([x, y], i) => i ? pen.lineTo(x, y) : pen.moveTo(x, y));
  pen.stroke();
  pen.strokeStyle = '#fff'; pen.lineWidth = 2; pen.beginPath();
  for (const [at, x0, y0, x1, y1] of run.segments) {
    if (at > t) break;
    pen.moveTo(x0, y0); pen.lineTo(x1, y1);
  }
  pen.stroke();
  let pose = run.poses[0];
  for (const p of run.poses) { if (p[0] > t) break; pose = p; }
  if (pose) {
    const [, x, y, theta] = pose;
    pen.save(); pen.translate(x, y); pen.rotate(-theta); pen.fillStyle = '#2e7d32';
    pen.beginPath(); pen.moveTo(12, 0); pen.lineTo(-8, 7); pen.lineTo(-8, -7); pen.fill();
    pen.restore();
  }
  clock.textContent = t.toFixed(2) + ' s of ' + end.toFixed(2) + ' s';
}
let timer = null;
document.getElementById('play').onclick = () => {
  if (timer) { clearInterval(timer); timer = null; return; }
  if (+slider.value >= end) slider.value = 0;
  timer = setInterval(() => {
    slider.value = Math.min(end, +slider.value + 0.05); draw(+slider.value);
    if (+slider.value >= end) { clearInterval(timer); timer = null; }
  }, 50);
};
slider.oninput = () => draw(+slider.value);
document.getElementById('calls').textContent = run.calls.length ?
  'services called: ' + run.calls.map(([t, name]) => name + ' at ' + t + ' s').join(', ') : '';
for (const [passed, text] of run.checks) {
  const item = document.createElement('li');
  item.className = passed ? 'pass' : 'fail';
  item.textContent = (passed ? '\\u2713 ' : '\\u2717 ') + text;
  document.getElementById('checks').appendChild(item);
}
slider.value = end; draw(end);
</script></body></html>
'''

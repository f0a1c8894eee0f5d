// turtle_traj live view: the simulator's canvas from its frames, and the page's requests.
'use strict';

const view = document.getElementById('view');
const sprites = document.getElementById('sprites');
const viewContext = view.getContext('2d');
const spriteContext = sprites.getContext('2d');
// The trail layer, exactly as the simulator holds it: frames write its changed pixels.
const trails = document.createElement('canvas');
trails.width = view.width;
trails.height = view.height;
const trailContext = trails.getContext('2d');
const icon = new Image();
icon.src = '/turtle.png';

const state = {
  world: null, background: [69, 86, 255], turtles: [], dirty: true, kinds: [],
  received: 0, rendered: 0, latencies: [], newestWall: null, lastSeq: 0, goalRunning: false,
};

const $ = (id) => document.getElementById(id);
const socket = new WebSocket(`ws://${location.host}/ws`);

function send(message) {
  if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function showError(text) { $('error').textContent = text; }

function pixels(base64, width, height) {
  const bytes = atob(base64);
  const data = new Uint8ClampedArray(bytes.length);
  for (let i = 0; i < bytes.length; i++) data[i] = bytes.charCodeAt(i);
  return new ImageData(data, width, height);
}

function setTurtles(turtles) {
  state.turtles = turtles;
  const select = $('turtle');
  const names = turtles.map((t) => t[0]);
  if ([...select.options].map((o) => o.value).join() !== names.join()) {
    const chosen = select.value;
    select.replaceChildren(...names.map((name) => new Option(name, name)));
    if (names.includes(chosen)) select.value = chosen;
  }
}

const handlers = {
  hello(message) {
    state.world = message.world;
    state.kinds = message.kinds;
    $('kind').replaceChildren(...message.kinds.map((k) => new Option(k.name, k.name)));
    showFields();
    send({type: 'get_params'});
  },
  snapshot(message) {
    trailContext.clearRect(0, 0, trails.width, trails.height);
    trailContext.putImageData(pixels(message.pixels, message.width, message.height), 0, 0);
    state.background = message.background;
    setTurtles(message.turtles);
    state.lastSeq = message.seq;
    state.dirty = true;
  },
  frame(message) {
    if (message.clear) trailContext.clearRect(0, 0, trails.width, trails.height);
    for (const [row, column, height, width, data] of message.patches) {
      trailContext.putImageData(pixels(data, width, height), column, row);
    }
    state.background = message.background;
    setTurtles(message.turtles);
    state.received += 1;
    state.lastSeq = message.seq;
    state.newestWall = message.wall;
    state.dirty = true;
  },
  status(message) {
    $('status').textContent = message.node ? 'trajectory node: ready' : message.why;
    $('start').disabled = !message.node || state.goalRunning;
  },
  stats(message) { $('stats').dataset.dropped = message.dropped; },
  run(message) {
    const running = message.state === 'running';
    state.goalRunning = running;
    $('cancel').disabled = !running;
    $('start').disabled = running;
    if (running) {
      $('progress').value = message.progress;
      $('run').textContent = `${message.trajectory}: running, ${Math.round(message.progress * 100)} %`;
    } else if (message.state === 'ended') {
      const result = message.result;
      $('progress').value = result.success ? 1 : $('progress').value;
      $('run').textContent = `${message.trajectory}: ${result.success ? 'done' : 'not done'}: ${result.message}`;
      $('result').replaceChildren(...Object.entries(result).filter(([k]) => k !== 'message').map(
        ([name, value]) => row(name, typeof value === 'number' ? value.toFixed(4) : String(value))));
    } else {
      $('run').textContent = `${message.trajectory}: rejected`;
    }
  },
  params(message) {
    const table = $('params');
    const inputs = new Map([...table.querySelectorAll('input')].map((i) => [i.name, i]));
    if (message.params.map((p) => p.name).join() !== [...inputs.keys()].join()) {
      table.replaceChildren(...message.params.map(paramRow));
      return;
    }
    for (const param of message.params) {  // in place: what is being typed stays
      const input = inputs.get(param.name);
      if (input !== document.activeElement) input.value = shown(param.value);
    }
  },
  param_result(message) {
    $('param-message').textContent = message.message;
    $('param-message').className = message.ok ? 'status' : 'error';
    send({type: 'get_params'});
  },
  error(message) { showError(message.message); },
};

function row(...cells) {
  const tr = document.createElement('tr');
  for (const cell of cells) {
    const td = document.createElement('td');
    if (cell instanceof Node) td.append(cell); else td.textContent = cell;
    tr.append(td);
  }
  return tr;
}

// A parameter's value as shown: a number to 6 significant digits (turtlesim's 11.0888... arena
// reads 11.0889), the rest as it is.
function shown(value) {
  return typeof value === 'number' && !Number.isInteger(value) ? String(+value.toPrecision(6))
    : String(value);
}

function paramRow(param) {
  const input = document.createElement('input');
  input.value = shown(param.value);
  input.name = param.name;
  input.disabled = param.read_only;
  input.title = param.description + (param.low !== null ? ` [${param.low}, ${param.high}]` : '');
  const set = document.createElement('button');
  set.textContent = 'Set';
  set.type = 'button';
  set.disabled = param.read_only;
  set.addEventListener('click', () => send({type: 'set_param', name: param.name, value: input.value}));
  return row(param.name, input, set);
}

function showFields() {
  const kind = state.kinds.find((k) => k.name === $('kind').value);
  $('summary').textContent = kind.summary;
  $('fields').replaceChildren(...kind.fields.map((field) => {
    const label = document.createElement('label');
    const input = document.createElement('input');
    input.name = field.name;
    input.dataset.type = field.type;
    if (field.type === 'bool') {
      input.type = 'checkbox';
      input.checked = Boolean(field.default);
    } else if (field.type === 'float' || field.type === 'int') {
      input.type = 'number';
      input.step = field.type === 'int' ? '1' : 'any';
      if (field.low !== null) input.min = field.low;
      if (field.high !== null) input.max = field.high;
      // Left empty, a field takes its default (or the node's parameter), as on the command line.
      // (a 0 that is not a parameter's stands for a default the request works out: 'auto')
      input.placeholder = field.parameter ? `node: ${field.parameter}`
        : (field.optional ? 'none' : (field.default === 0 ? 'auto' : `default: ${field.default}`));
    } else {
      input.type = 'text';
      input.placeholder = field.type === 'points' ? 'x,y x,y …'
        : (field.default ? `default: ${field.default}` : '');
    }
    const unit = field.unit ? ` [${field.unit}]` : '';
    const range = field.low !== null && field.high !== null ? ` ${field.low} to ${field.high}` : '';
    label.title = field.help + range;
    label.append(`${field.name}${unit}`, input);
    return label;
  }));
}

function fieldValues() {
  const values = {};
  for (const input of $('fields').querySelectorAll('input')) {
    const type = input.dataset.type;
    if (type === 'bool') values[input.name] = input.checked;
    else if (input.value.trim() === '') continue;
    else if (type === 'float' || type === 'int') values[input.name] = Number(input.value);
    else if (type === 'points') {
      values[input.name] = input.value.trim().split(/\s+/).map((p) => p.split(',').map(Number));
    } else values[input.name] = input.value;
  }
  return values;
}

function render() {
  if (state.dirty && state.world) {
    state.dirty = false;
    const [r, g, b] = state.background;
    viewContext.fillStyle = `rgb(${r}, ${g}, ${b})`;
    viewContext.fillRect(0, 0, view.width, view.height);
    viewContext.drawImage(trails, 0, 0);
    spriteContext.clearRect(0, 0, sprites.width, sprites.height);
    const scale = state.world.pixels_per_meter;
    for (const [, x, y, theta] of state.turtles) {
      spriteContext.save();
      spriteContext.translate(x * scale, (state.world.size_m - y) * scale);
      spriteContext.rotate(Math.PI / 2 - theta);
      if (icon.complete) spriteContext.drawImage(icon, -icon.width / 2, -icon.height / 2);
      spriteContext.restore();
    }
    state.rendered += 1;
    if (state.newestWall !== null) {
      state.latencies.push(Date.now() / 1000 - state.newestWall);
      if (state.latencies.length > 2000) state.latencies.shift();
      state.newestWall = null;
    }
  }
  requestAnimationFrame(render);
}

socket.addEventListener('open', () => { $('connection').textContent = 'live'; });
socket.addEventListener('close', () => { $('connection').textContent = 'disconnected'; });
socket.addEventListener('message', (event) => {
  const message = JSON.parse(event.data);
  const handler = handlers[message.type];
  if (handler) handler(message);
});

const ARROWS = {ArrowUp: 'up', ArrowDown: 'down', ArrowLeft: 'left', ArrowRight: 'right'};
document.addEventListener('keydown', (event) => {
  if (['INPUT', 'SELECT', 'TEXTAREA'].includes(event.target.tagName)) return;
  const key = ARROWS[event.key] || (/^[gtredcvbf]$/i.test(event.key) ? event.key.toLowerCase() : null);
  if (!key) return;
  event.preventDefault();
  send({type: 'key', turtle: $('turtle').value || 'turtle1', key});
});

view.addEventListener('click', (event) => {
  if (!state.world) return;
  const box = view.getBoundingClientRect();
  const px = (event.clientX - box.left) * view.width / box.width;
  const py = (event.clientY - box.top) * view.height / box.height;
  const scale = state.world.pixels_per_meter;
  send({type: 'goto', x: px / scale, y: state.world.size_m - py / scale});
});

$('kind').addEventListener('change', showFields);
$('trajectory').addEventListener('submit', (event) => {
  event.preventDefault();
  showError('');
  $('result').replaceChildren();
  $('progress').value = 0;
  send({type: 'start', trajectory: $('kind').value, fields: fieldValues()});
});
$('cancel').addEventListener('click', () => send({type: 'cancel'}));
$('reload').addEventListener('click', () => send({type: 'get_params'}));

setInterval(() => {
  const sorted = [...state.latencies].sort((a, b) => a - b);
  const p95 = sorted.length ? sorted[Math.floor(0.95 * (sorted.length - 1))] : NaN;
  $('stats').textContent = `frames ${state.received}, latency p95 ${(p95 * 1000).toFixed(0)} ms`;
}, 1000);
requestAnimationFrame(render);

// For tests and benchmarks (selenium): the canvas as a PNG, and the page's own figures.
window.turtleTraj = {
  viewPNG: () => view.toDataURL('image/png'),
  stats: () => ({received: state.received, rendered: state.rendered, lastSeq: state.lastSeq,
                 latencies: state.latencies.slice(), turtles: state.turtles}),
};

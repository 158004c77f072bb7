// The dashboard page: draws what /api/stream sends (see docs/DASHBOARD.md). Plain JavaScript, no
// libraries. window.ctsfleet exposes the page's state for tests and for the curious.
"use strict";

const view = {
  mission: null,      // /api/mission
  plan: null,         // /api/plan
  frame: null,        // the last frame
  drawn: {},          // robot id -> {x, y}: where it is drawn now (cells, moving smoothly)
  lastSeq: {},        // robot id -> the last state sequence number seen
  latencies: [],      // ms from a state reaching the dashboard to this page, newest last
  frames: 0,
  laidOut: false,     // the layers are sized for the mission
  plansKey: "",       // what the tasks-and-plans layer shows
  scale: 1,
  dirty: true,        // something to draw again
  panelsDue: 0,       // when the side panels may be rendered again (performance.now())
  eventsShown: -1,
};
const kRobotsListed = 300;  // rows of the robots table (and robots in the task menu)

// Three stacked canvases: walls (drawn once per mission), tasks and plans (drawn again a few times a
// second at most, when they change), robots (animated; on top, it takes the clicks).
const walls = document.getElementById("map-walls");
const plans = document.getElementById("map-plans");
const canvas = document.getElementById("map");
const context = canvas.getContext("2d");
const statusColours = {
  moving: "#1b873f", delayed: "#e64a19", waiting: "#e0a100", parked: "#2d5bd3", fault: "#c62828", off_plan: "#d81b60",
  lost: "#9e9e9e", left: "#9e9e9e", joining: "#607d8b",
};
const taskColours = { pending: "#ff9800", pool: "#fdd835", done: "#43a047", cancelled: "#bdbdbd", unassigned: "#e53935" };

function robotColour(id) {
  let hash = 0;
  for (const c of id) hash = (hash * 31 + c.charCodeAt(0)) >>> 0;
  return `hsl(${Math.round((hash * 137.508) % 360)}, 65%, 45%)`;  // the golden angle: neighbours differ
}

function percentile(values, p) {
  if (values.length === 0) return null;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.floor(sorted.length * p))];
}

// --- The map -------------------------------------------------------------------------------

function layout() {
  const m = view.mission;
  if (!m) return;
  const room = Math.min(window.innerWidth * 0.6, window.innerHeight - 120, 900);
  view.scale = Math.max(2, Math.floor(room / Math.max(m.width, m.height)));
  for (const layer of [walls, plans, canvas]) {
    layer.width = m.width * view.scale;
    layer.height = m.height * view.scale;
  }
  const g = walls.getContext("2d");
  g.fillStyle = "#ffffff";
  g.fillRect(0, 0, walls.width, walls.height);
  g.fillStyle = "#37474f";
  m.rows.forEach((row, y) => {
    for (let x = 0; x < row.length; ++x) {
      if (row[x] !== ".") g.fillRect(x * view.scale, y * view.scale, view.scale, view.scale);
    }
  });
  view.laidOut = true;
  view.plansKey = "";  // the scale may have changed
  view.dirty = true;
}

function cellCentre(x, y) {
  return [(x + 0.5) * view.scale, (y + 0.5) * view.scale];
}

function isFree(x, y) {
  const m = view.mission;
  return m && y >= 0 && y < m.height && x >= 0 && x < m.width && m.rows[y][x] === ".";
}

// Tasks (a square each, coloured by its state) and the remaining paths, on the middle layer: drawn
// again only when they change, and at most five times a second (paths are the page's most
// expensive drawing with a hundred robots; a path a fifth of a second old is as good to an operator).
// Returns true when a change waits for a later frame.
let plansDrawn = 0;
function drawTasksAndPlans(f, now) {
  const m = view.mission;
  const version = view.plan ? view.plan.version : -1;
  const key = `${m.version}|${version}|${f ? f.tasks.join() : ""}|` +
              (f ? f.robots.map((r) => `${r.id}:${r.path_from}:${r.status}`).join() : "");
  if (key === view.plansKey) return false;
  if (view.plansKey !== "" && now - plansDrawn < 200) return true;  // changed: drawn on a later frame
  view.plansKey = key;
  plansDrawn = now;
  const g = plans.getContext("2d");
  const s = view.scale;
  g.clearRect(0, 0, plans.width, plans.height);
  const states = f ? f.tasks : [];
  m.tasks.forEach((task, i) => {
    const state = task.cancelled ? "cancelled" : states[i] || "pending";
    g.fillStyle = taskColours[state];
    g.globalAlpha = state === "done" || state === "cancelled" ? 0.45 : 0.9;
    g.fillRect(task.x * s + s * 0.15, task.y * s + s * 0.15, s * 0.7, s * 0.7);
  });
  g.globalAlpha = 0.5;
  g.lineWidth = Math.max(1, s * 0.15);
  for (const robot of f ? f.robots : []) {
    const plan = view.plan && view.plan.robots[robot.id];
    if (!plan || robot.path_from < 0 || robot.status === "lost" || robot.status === "left") continue;
    const rest = plan.path.slice(Math.max(0, robot.path_from - 1));
    if (rest.length === 0) continue;
    g.strokeStyle = robotColour(robot.id);
    g.beginPath();
    g.moveTo(...cellCentre(rest[0][0], rest[0][1]));
    for (const [x, y] of rest.slice(1)) g.lineTo(...cellCentre(x, y));
    // Its goal: a ring at the path's end.
    const end = plan.path[plan.path.length - 1];
    g.moveTo(...cellCentre(end[0] + 0.3, end[1]));
    g.arc(...cellCentre(end[0], end[1]), s * 0.3, 0, 2 * Math.PI);
    g.stroke();
  }
  g.globalAlpha = 1;
  return false;
}

// Each robot is drawn from a sprite (its disc, outline and label, made once per look and scale):
// copying a small image is much cheaper than filling a path and shaping text, thirty times a second.
const sprites = new Map();  // "id|status|scale" -> canvas
const kSmallestSprite = 6;  // pixels per cell below which robots are drawn as squares
function robotSprite(robot, s) {
  const key = `${robot.id}|${robot.status}|${s}`;
  let sprite = sprites.get(key);
  if (sprite) return sprite;
  const labelled = s >= 12;
  sprite = document.createElement("canvas");
  sprite.width = Math.ceil(s * (labelled ? 2.6 : 1));
  sprite.height = Math.ceil(s * (labelled ? 1.4 : 1));
  const g = sprite.getContext("2d");
  const cx = s * 0.5, cy = sprite.height - s * 0.5;
  g.beginPath();
  g.arc(cx, cy, s * 0.42, 0, 2 * Math.PI);
  g.fillStyle = robot.status === "lost" || robot.status === "left" ? "#e0e0e0" : robotColour(robot.id);
  g.fill();
  g.lineWidth = Math.max(2, s * 0.12);
  g.strokeStyle = statusColours[robot.status] || "#000";
  g.setLineDash(robot.status === "lost" ? [3, 3] : []);
  g.stroke();
  if (labelled) {
    g.fillStyle = "#000";
    g.font = `${Math.max(9, s * 0.45)}px system-ui`;
    g.fillText(robot.id.replace(/^robot/, "r"), cx + s * 0.45, cy - s * 0.35);
  }
  if (sprites.size > Math.max(5000, 3 * (view.frame ? view.frame.robots.length : 0))) sprites.clear();
  sprites.set(key, sprite);
  return sprite;
}

let lastDraw = 0;
function draw(now) {
  requestAnimationFrame(draw);
  const f = view.frame;
  if (!view.mission || !view.laidOut || !view.dirty || now - lastDraw < 33) return;  // at most 30 frames per second
  lastDraw = now;
  const gliding = glide(now);
  view.dirty = drawTasksAndPlans(f, now) || gliding;  // something still to draw on a later frame
  const s = view.scale;
  context.clearRect(0, 0, canvas.width, canvas.height);
  for (const robot of f ? f.robots : []) {
    const at = view.drawn[robot.id];
    if (!at) continue;
    if (s < kSmallestSprite) {  // a big map: each robot a square of its status's colour, no sprites
      context.fillStyle = statusColours[robot.status] || "#000";
      context.fillRect(at.x * s, at.y * s, Math.max(1, s), Math.max(1, s));
      continue;
    }
    const sprite = robotSprite(robot, s);
    context.drawImage(sprite, Math.round(at.x * s), Math.round((at.y + 1) * s - sprite.height));
  }
}

// Robots glide towards their reported pose: an exponential approach with a 100 ms time constant.
// Returns true while some robot is still on its way (the next animation frame must draw).
let lastGlide = performance.now();
function glide(now) {
  const blend = Math.min(1, (now - lastGlide) / 100);
  lastGlide = now;
  let moving = false;
  for (const robot of view.frame ? view.frame.robots : []) {
    if (robot.x === undefined) continue;
    const target = { x: robot.pose_x ?? robot.x, y: robot.pose_y ?? robot.y };
    const at = view.drawn[robot.id];
    if (!at || Math.hypot(target.x - at.x, target.y - at.y) > 3) {
      view.drawn[robot.id] = { ...target };  // first sight, or a jump: no gliding across the map
    } else {
      at.x += (target.x - at.x) * blend;
      at.y += (target.y - at.y) * blend;
      if (Math.hypot(target.x - at.x, target.y - at.y) > 0.01) {
        moving = true;
      } else {
        at.x = target.x;
        at.y = target.y;
      }
    }
  }
  return moving;
}

// --- Panels --------------------------------------------------------------------------------

function text(value, digits = 0) {
  return value === null || value === undefined ? "–" : typeof value === "number" ? value.toFixed(digits) : value;
}

function renderPanels() {
  const f = view.frame;
  if (!f || performance.now() < view.panelsDue) return;
  view.panelsDue = performance.now() + 500;  // twice a second is plenty for tables
  const c = f.coordinator;
  document.getElementById("coordinator").textContent =
    c ? `coordinator ${c.id.slice(0, 8)} (${c.role}, term ${c.term}, epoch ${c.epoch})` : "no coordinator heard";
  const p = f.progress;
  document.getElementById("progress").textContent =
    p ? `tasks ${p.tasks_done}/${p.tasks_total} · robots ${p.robots}` : "";
  const fig = f.figures || {};
  const rows = [
    ["command round trip p50 / p99", `${text(fig.round_trip_p50_ms, 1)} / ${text(fig.round_trip_p99_ms, 1)} ms`],
    ["last planning time", `${text(fig.last_planning_ms)} ms`],
    ["last replan latency", `${text(fig.last_replan_latency_ms)} ms`],
    ["steps done / planned", `${text(fig.steps_done)} / ${text(fig.steps_planned)}`],
    ["plan flowtime", view.plan ? text(view.plan.flowtime) : "–"],
    ["page latency p50 / p99", `${text(percentile(view.latencies, 0.5))} / ${text(percentile(view.latencies, 0.99))} ms`],
  ];
  // Every string the page shows goes in as text, never as markup: robot ids, event texts and
  // figures come from the network and may hold anything.
  document.getElementById("figures").replaceChildren(...rows.map(([name, value]) => {
    const row = document.createElement("tr");
    for (const cell of [name, value]) row.insertCell().textContent = cell;
    return row;
  }));
  renderSchedule(f.schedule);
  // A fleet of thousands (a big plan shown) lists its first robots only: a table or a menu of
  // ten thousand rows helps nobody and costs the page most of a core.
  const listed = f.robots.slice(0, kRobotsListed);
  renderRobotTable(listed);
  const cut = document.getElementById("robots-cut");
  cut.hidden = listed.length === f.robots.length;
  cut.textContent = `the first ${listed.length} of ${f.robots.length} robots`;
  const select = document.getElementById("task-robot");
  const ids = listed.filter((r) => r.role >= 0).map((r) => r.id);
  const have = [...select.options].slice(1).map((o) => o.value);
  if (ids.join() !== have.join()) {
    const chosen = select.value;
    select.length = 1;
    for (const id of ids) select.add(new Option(id, id));
    select.value = ids.includes(chosen) ? chosen : "";
  }
  if (view.eventsShown === f.events_total) return;
  view.eventsShown = f.events_total;
  document.getElementById("events").replaceChildren(...[...f.events].reverse().map((e) => {
    const item = document.createElement("li");
    const kind = document.createElement("span");
    kind.className = `kind kind-${String(e.kind).replace(/[^a-z_]/g, "")}`;
    kind.textContent = e.kind;
    const time = new Date(e.stamp_ms).toLocaleTimeString();
    item.append(kind, ` ${time} ${e.robot ? e.robot + ": " : ""}${e.text}`);
    return item;
  }));
}

// Where the fleet's tasks stand, and which robots are late now.
const kDelayedListed = 20;
function renderSchedule(schedule) {
  const table = document.getElementById("schedule");
  if (!schedule) {
    table.replaceChildren();
    return;
  }
  const delayed = schedule.delayed.slice(0, kDelayedListed).join(", ") +
                  (schedule.delayed.length > kDelayedListed ? ", …" : "");
  const rows = [
    ["tasks in robots' plans", String(schedule.in_plans)],
    ["tasks waiting in the pool", String(schedule.pool)],
    ["tasks without a robot for their role", String(schedule.unassigned)],
    [`robots delayed now (a move over ${text(schedule.late_after_ms)} ms)`,
     schedule.delayed.length ? `${schedule.delayed.length}: ${delayed}` : "0"],
    ["typical move", `${text(schedule.typical_move_ms)} ms`],
  ];
  table.replaceChildren(...rows.map(([name, value]) => {
    const row = document.createElement("tr");
    for (const cell of [name, value]) row.insertCell().textContent = cell;
    return row;
  }));
}

function firstTaskIn(r) {
  if (r.next_tasks.length === 0) return "–";
  return r.task_steps >= 0 ? `${r.task_steps} steps` : "pool";
}

// One row per robot, kept from frame to frame: only the cells whose text changed are touched (a
// table rebuilt twice a second for a hundred robots cost the page a tenth of a core).
const robotRows = new Map();  // robot id -> [td...]
function renderRobotTable(robots) {
  const body = document.querySelector("#robots tbody");
  const seen = new Set();
  for (const r of robots) {
    seen.add(r.id);
    let cells = robotRows.get(r.id);
    if (!cells) {
      const row = body.insertRow();
      row.dataset.robot = r.id;
      cells = [...Array(8)].map(() => row.insertCell());
      robotRows.set(r.id, cells);
    }
    const values = [r.id, r.status, r.role >= 0 ? String(r.role) : "–", r.x === undefined ? "–" : `(${r.x},${r.y})`,
                    r.battery >= 0 ? `${r.battery}%` : "–", String(r.next_tasks.length), firstTaskIn(r),
                    r.next_tasks.slice(0, 6).join(", ")];
    values.forEach((value, i) => {
      if (cells[i].textContent !== value) cells[i].textContent = value;
    });
    const statusClass = `status-${r.status}`;
    if (cells[1].className !== statusClass) cells[1].className = statusClass;
  }
  for (const [id, cells] of robotRows) {
    if (!seen.has(id)) {
      cells[0].parentElement.remove();
      robotRows.delete(id);
    }
  }
}

// --- The stream ----------------------------------------------------------------------------

function onFrame(frame) {
  const received = Date.now();
  for (const robot of frame.robots) {
    if (robot.seq === undefined || view.lastSeq[robot.id] === robot.seq) continue;
    view.lastSeq[robot.id] = robot.seq;
    if (!frame.replay) view.latencies.push(received - robot.heard_ms);  // same host: one clock
  }
  if (view.latencies.length > 5000) view.latencies.splice(0, view.latencies.length - 5000);
  view.frame = frame;
  view.dirty = true;
  ++view.frames;
  document.getElementById("replay").hidden = !frame.replay;
  renderPanels();
}

function connect() {
  const source = new EventSource("/api/stream");
  const connection = document.getElementById("connection");
  source.onopen = () => { connection.textContent = "live"; connection.className = "good"; };
  source.onerror = () => { connection.textContent = "reconnecting…"; connection.className = "bad"; };
  source.addEventListener("mission", (e) => { view.mission = JSON.parse(e.data); layout(); view.dirty = true; });
  source.addEventListener("plan", (e) => { view.plan = JSON.parse(e.data); view.dirty = true; });
  source.addEventListener("frame", (e) => onFrame(JSON.parse(e.data)));
}

// --- Giving work -------------------------------------------------------------------------

async function addTask(x, y, robot) {
  const result = document.getElementById("task-result");
  result.textContent = `asking for a task at (${x},${y})…`;
  const response = await fetch("/api/tasks", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ action: "add", x, y, robot }),
  });
  const answer = await response.json();
  result.textContent = answer.accepted ? answer.reason : `refused: ${answer.reason}`;
  result.className = answer.accepted ? "" : "status-fault";
  return answer;
}

canvas.addEventListener("click", (event) => {
  const box = canvas.getBoundingClientRect();
  const x = Math.floor((event.clientX - box.left) / view.scale);
  const y = Math.floor((event.clientY - box.top) / view.scale);
  if (!isFree(x, y)) {
    document.getElementById("task-result").textContent = `(${x},${y}) is not a free cell`;
    return;
  }
  addTask(x, y, document.getElementById("task-robot").value);
});

for (const button of document.querySelectorAll("#replay button")) {
  button.addEventListener("click", () => fetch("/api/replay", {
    method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify({ speed: Number(button.dataset.speed) }),
  }));
}
window.addEventListener("resize", () => { layout(); view.plansKey = ""; view.dirty = true; });

window.ctsfleet = {
  view,
  // Where each robot is drawn, in cells (fractional while it glides), and its status.
  drawn: () => Object.fromEntries((view.frame ? view.frame.robots : []).filter((r) => view.drawn[r.id])
    .map((r) => [r.id, { x: view.drawn[r.id].x, y: view.drawn[r.id].y, status: r.status }])),
  // The page coordinates (CSS pixels, from the canvas's top-left corner) of a cell's centre.
  cellOffset: (x, y) => cellCentre(x, y),
  latencies: () => [...view.latencies],
};

connect();
requestAnimationFrame(draw);

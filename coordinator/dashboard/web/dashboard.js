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
  mapImage: null,     // the map's walls, drawn once per mission
  scale: 1,
};

const canvas = document.getElementById("map");
const context = canvas.getContext("2d");
const statusColours = {
  moving: "#1b873f", waiting: "#e0a100", parked: "#2d5bd3", fault: "#c62828", off_plan: "#d81b60",
  lost: "#9e9e9e", left: "#9e9e9e", joining: "#607d8b",
};
const taskColours = { pending: "#ff9800", done: "#43a047", cancelled: "#bdbdbd", unassigned: "#e53935" };

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
  canvas.width = m.width * view.scale;
  canvas.height = m.height * view.scale;
  const image = document.createElement("canvas");
  image.width = canvas.width;
  image.height = canvas.height;
  const g = image.getContext("2d");
  g.fillStyle = "#ffffff";
  g.fillRect(0, 0, image.width, image.height);
  g.fillStyle = "#37474f";
  m.rows.forEach((row, y) => {
    for (let x = 0; x < row.length; ++x) {
      if (row[x] !== ".") g.fillRect(x * view.scale, y * view.scale, view.scale, view.scale);
    }
  });
  view.mapImage = image;
}

function cellCentre(x, y) {
  return [(x + 0.5) * view.scale, (y + 0.5) * view.scale];
}

function isFree(x, y) {
  const m = view.mission;
  return m && y >= 0 && y < m.height && x >= 0 && x < m.width && m.rows[y][x] === ".";
}

function draw() {
  const m = view.mission;
  const f = view.frame;
  if (!m || !view.mapImage) {
    requestAnimationFrame(draw);
    return;
  }
  const s = view.scale;
  context.drawImage(view.mapImage, 0, 0);
  // Tasks: a square per task, coloured by its state.
  const states = f ? f.tasks : [];
  m.tasks.forEach((task, i) => {
    const state = task.cancelled ? "cancelled" : states[i] || "pending";
    context.fillStyle = taskColours[state];
    context.globalAlpha = state === "done" || state === "cancelled" ? 0.45 : 0.9;
    context.fillRect(task.x * s + s * 0.15, task.y * s + s * 0.15, s * 0.7, s * 0.7);
  });
  context.globalAlpha = 1;
  if (f) {
    // Remaining plans, then robots on top.
    for (const robot of f.robots) {
      const plan = view.plan && view.plan.robots[robot.id];
      const at = view.drawn[robot.id];
      if (!plan || !at || robot.path_from < 0 || robot.status === "lost" || robot.status === "left") continue;
      context.strokeStyle = robotColour(robot.id);
      context.globalAlpha = 0.5;
      context.lineWidth = Math.max(1, s * 0.15);
      context.beginPath();
      context.moveTo(...cellCentre(at.x, at.y));
      for (const [x, y] of plan.path.slice(robot.path_from)) context.lineTo(...cellCentre(x, y));
      context.stroke();
      // Its goal: a ring at the path's end.
      const end = plan.path[plan.path.length - 1];
      context.beginPath();
      context.arc(...cellCentre(end[0], end[1]), s * 0.3, 0, 2 * Math.PI);
      context.stroke();
      context.globalAlpha = 1;
    }
    for (const robot of f.robots) {
      const at = view.drawn[robot.id];
      if (!at) continue;
      const [px, py] = cellCentre(at.x, at.y);
      context.beginPath();
      context.arc(px, py, s * 0.42, 0, 2 * Math.PI);
      context.fillStyle = robot.status === "lost" || robot.status === "left" ? "#e0e0e0" : robotColour(robot.id);
      context.fill();
      context.lineWidth = Math.max(2, s * 0.12);
      context.strokeStyle = statusColours[robot.status] || "#000";
      context.setLineDash(robot.status === "lost" ? [3, 3] : []);
      context.stroke();
      context.setLineDash([]);
      if (s >= 12) {
        context.fillStyle = "#000";
        context.font = `${Math.max(9, s * 0.45)}px system-ui`;
        context.fillText(robot.id.replace(/^robot/, "r"), px + s * 0.45, py - s * 0.35);
      }
    }
  }
  requestAnimationFrame(draw);
}

// Robots glide towards their reported pose: an exponential approach with a 100 ms time constant.
let lastTick = performance.now();
function glide() {
  const now = performance.now();
  const blend = Math.min(1, (now - lastTick) / 100);
  lastTick = now;
  if (view.frame) {
    for (const robot of view.frame.robots) {
      if (robot.x === undefined) continue;
      const target = { x: robot.pose_x ?? robot.x, y: robot.pose_y ?? robot.y };
      const at = view.drawn[robot.id];
      if (!at || Math.hypot(target.x - at.x, target.y - at.y) > 3) {
        view.drawn[robot.id] = { ...target };  // first sight, or a jump: no gliding across the map
      } else {
        at.x += (target.x - at.x) * blend;
        at.y += (target.y - at.y) * blend;
      }
    }
  }
  setTimeout(glide, 16);
}

// --- Panels --------------------------------------------------------------------------------

function text(value, digits = 0) {
  return value === null || value === undefined ? "–" : typeof value === "number" ? value.toFixed(digits) : value;
}

function renderPanels() {
  const f = view.frame;
  if (!f) return;
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
  document.getElementById("figures").innerHTML =
    rows.map(([name, value]) => `<tr><td>${name}</td><td>${value}</td></tr>`).join("");
  const body = document.querySelector("#robots tbody");
  body.innerHTML = f.robots.map((r) => `<tr data-robot="${r.id}">
      <td>${r.id}</td><td class="status-${r.status}">${r.status}</td><td>${r.role >= 0 ? r.role : "–"}</td>
      <td>${r.x === undefined ? "–" : `(${r.x},${r.y})`}</td><td>${r.battery >= 0 ? r.battery + "%" : "–"}</td>
      <td>${r.next_tasks.length}</td><td>${r.next_tasks.slice(0, 6).join(", ")}</td></tr>`).join("");
  const select = document.getElementById("task-robot");
  const ids = f.robots.filter((r) => r.role >= 0).map((r) => r.id);
  const have = [...select.options].slice(1).map((o) => o.value);
  if (ids.join() !== have.join()) {
    const chosen = select.value;
    select.length = 1;
    for (const id of ids) select.add(new Option(id, id));
    select.value = ids.includes(chosen) ? chosen : "";
  }
  document.getElementById("events").innerHTML = [...f.events].reverse().map((e) => {
    const time = new Date(e.stamp_ms).toLocaleTimeString();
    return `<li><span class="kind kind-${e.kind}">${e.kind}</span> ${time} ${e.robot ? e.robot + ": " : ""}${escapeHtml(e.text)}</li>`;
  }).join("");
}

function escapeHtml(s) {
  return s.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
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
  ++view.frames;
  document.getElementById("replay").hidden = !frame.replay;
  renderPanels();
}

function connect() {
  const source = new EventSource("/api/stream");
  const connection = document.getElementById("connection");
  source.onopen = () => { connection.textContent = "live"; connection.className = "good"; };
  source.onerror = () => { connection.textContent = "reconnecting…"; connection.className = "bad"; };
  source.addEventListener("mission", (e) => { view.mission = JSON.parse(e.data); layout(); });
  source.addEventListener("plan", (e) => { view.plan = JSON.parse(e.data); });
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
window.addEventListener("resize", layout);

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
glide();
requestAnimationFrame(draw);

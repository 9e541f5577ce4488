// The match viewer: draws the frames the server streams over /ws, sends coach commands and replay controls.
// World frame [m]: x to the right, y up. Everything here is served by the viewer itself (no internet needed).
"use strict";

const canvas = document.getElementById("field");
const ctx = canvas.getContext("2d");
const token = new URLSearchParams(location.search).get("token") || "";
const ROLE_SHORT = {GOALIE: "G", ACTIVE: "A", PASSIVE: "P", MIDFIELD: "M", ASSISTANT: "AS", ACIDPASSIVE: "AP",
  GAZER: "GZ", BLOCK: "B", NOROLE: "", CATCHOFPASS: "C", PASSOFPASS: "PS"};
const COMMAND_LABELS = {STOPROBOT: "Stop", STARTROBOT: "Start", DROPBALL: "Drop ball", PARKINGROBOT: "Park"};

let socket = null;
let hello = null;
let frame = null;
let replay = null; // {t, playing, speed} of the last frame (replay mode)
let sliderHeld = false;
const stats = {frames: 0, drawn: 0, fps: 0, moved: 0, commandsSent: 0, results: [], errors: []};
window.viewerStats = stats; // read by the tests
window.viewerFrame = () => frame;

function commandLabel(name) {
  if (COMMAND_LABELS[name]) return COMMAND_LABELS[name];
  const [who, ...rest] = name.split("_");
  const what = rest.join(" ").toLowerCase().replace("kick", " kick").replace("throwin", "throw-in");
  return `${what} (${who === "OUR" ? "ours" : "theirs"})`;
}

// ---- connection ---------------------------------------------------------------------------------------------

function connect() {
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  socket = new WebSocket(`${scheme}://${location.host}/ws`);
  socket.onopen = () => { setLink("live"); sendWatch(); };
  socket.onclose = () => { setLink("disconnected, retrying"); setTimeout(connect, 1000); };
  socket.onmessage = (event) => {
    const message = JSON.parse(event.data);
    if (message.type === "hello") onHello(message);
    else if (message.type === "frame") onFrame(message);
    else if (message.type === "result") onResult(message);
    else if (message.type === "error") onError(message);
  };
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function setLink(text) { document.getElementById("link").textContent = text; }

// ---- messages ------------------------------------------------------------------------------------------------

function onHello(message) {
  hello = message;
  setLink(message.mode === "replay" ? "replay" : "live");
  document.title = `${message.mode === "replay" ? "Replay" : "Live"}: ${message.title || "match"}`;
  document.getElementById("coach-panel").hidden = message.mode === "replay";
  document.getElementById("belief-panel").hidden = message.mode === "replay";
  const panel = document.getElementById("replay-panel");
  panel.hidden = message.mode !== "replay";
  if (message.mode === "replay") setUpReplay(message.replay);
  fillTeams(message.teams || []);
  fillCommands(message.commands || []);
  fitCanvas();
}

function onFrame(message) {
  if (frame) {  // frames in which some robot moved (the tests read it)
    const before = new Map(frame.robots.map((r) => [r.name, r]));
    if (message.robots.some((r) => before.has(r.name) && (before.get(r.name).x !== r.x || before.get(r.name).y !== r.y)))
      stats.moved += 1;
  }
  frame = message;
  stats.frames += 1;
  if (!drawPending) {  // draw once per display refresh, the latest frame only: a slow page skips, never lags
    drawPending = true;
    requestAnimationFrame(show);
  }
}

let drawPending = false;
function show() {
  drawPending = false;
  stats.drawn += 1;
  if (frame.replay) { replay = frame.replay; showReplay(); }
  updateTeams(frame.teams);
  updateWatchList(frame.robots);
  showScore(frame);
  showEvents(frame.referee.events);
  draw();
}

function onResult(message) {
  stats.results.push(message);
  const line = document.getElementById("result");
  line.textContent = `${message.command} for ${message.team}: ${message.message}`;
  line.className = message.ok ? "ok" : "refused";
}

function onError(message) {
  stats.errors.push(message.message);
  const line = document.getElementById("result");
  line.textContent = message.message;
  line.className = "refused";
}

let countedFrames = 0, countedAt = performance.now();
setInterval(() => {  // frames per second over the last interval, however late the timer fires
  const now = performance.now();
  stats.fps = Math.round((1000 * (stats.frames - countedFrames)) / Math.max(1, now - countedAt));
  countedFrames = stats.frames;
  countedAt = now;
  document.getElementById("fps").textContent = stats.fps;
}, 1000);

// ---- coach ---------------------------------------------------------------------------------------------------

let teamChosen = false; // the user picked a team: keep it; else the referee's first team
document.getElementById("team").onchange = () => { teamChosen = true; };

function fillTeams(teams) {
  const select = document.getElementById("team");
  const chosen = select.value;
  select.innerHTML = "";
  for (const team of teams) select.add(new Option(team, team));
  if (teamChosen && teams.includes(chosen)) select.value = chosen;
}

function updateTeams(teams) {
  const names = teams.map((t) => t.name);
  const select = document.getElementById("team");
  const have = Array.from(select.options).map((o) => o.value);
  if (names.join() !== have.join()) fillTeams(names);
}

function fillCommands(commands) {
  const box = document.getElementById("commands");
  box.innerHTML = "";
  for (const command of commands) {
    const button = document.createElement("button");
    button.textContent = commandLabel(command.name);
    button.title = `${command.name} (${command.value})`;
    button.dataset.command = command.name;
    if (command.name === "STOPROBOT") button.className = "stop";
    if (command.name === "STARTROBOT") button.className = "start";
    button.onclick = () => sendCommand(command.name);
    box.appendChild(button);
  }
}

function sendCommand(name) {
  stats.commandsSent += 1;
  send({type: "command", command: name, team: document.getElementById("team").value, token});
}

document.addEventListener("keydown", (event) => {
  if (event.code === "Space" && hello && hello.mode !== "replay" && event.target.tagName !== "INPUT") {
    event.preventDefault();
    sendCommand("STOPROBOT");
  }
});

// ---- world model toggle ----------------------------------------------------------------------------------------

const watchSelect = document.getElementById("watch");
watchSelect.onchange = sendWatch;

function sendWatch() { send({type: "watch", robot: watchSelect.value}); }

function updateWatchList(robots) {
  const names = robots.map((r) => r.name).sort();
  const have = Array.from(watchSelect.options).slice(1).map((o) => o.value);
  if (names.join() === have.join()) return;
  const chosen = watchSelect.value;
  watchSelect.length = 1;
  for (const name of names) watchSelect.add(new Option(name, name));
  watchSelect.value = names.includes(chosen) ? chosen : "";
}

// ---- replay ---------------------------------------------------------------------------------------------------

function setUpReplay(info) {
  const slider = document.getElementById("slider");
  slider.min = info.start;
  slider.max = info.end;
  slider.oninput = () => { sliderHeld = true; };
  slider.onchange = () => { send({type: "replay", action: "seek", t: Number(slider.value)}); sliderHeld = false; };
  document.getElementById("play").onclick = () =>
    send({type: "replay", action: replay && replay.playing ? "pause" : "play"});
  document.getElementById("speed").onchange = (e) =>
    send({type: "replay", action: "speed", speed: Number(e.target.value)});
  const marks = document.getElementById("marks");
  marks.innerHTML = "";
  for (const mark of info.marks) {
    const item = document.createElement("li");
    item.className = mark.kind;
    item.textContent = `${clock(mark.t - info.start)} ${mark.text}`;
    item.onclick = () => send({type: "replay", action: "seek", t: mark.t});
    marks.appendChild(item);
  }
}

function showReplay() {
  const slider = document.getElementById("slider");
  if (!sliderHeld) slider.value = replay.t;
  document.getElementById("play").textContent = replay.playing ? "Pause" : "Play";
  document.getElementById("replay-time").textContent =
    `${clock(replay.t - hello.replay.start)} / ${clock(hello.replay.end - hello.replay.start)}`;
}

// ---- score, clock, events -------------------------------------------------------------------------------------

function clock(seconds) {
  const s = Math.max(0, Math.floor(seconds || 0));
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, "0")}`;
}

function colourOf(team) {
  const t = frame && frame.teams.find((x) => x.name === team);
  return t ? t.colour : "#cccccc";
}

function showScore(message) {
  const ref = message.referee;
  const score = document.getElementById("score");
  if (!ref.teams.length) {
    score.innerHTML = "<span class='wait'>no referee</span>";
  } else {
    score.innerHTML = ref.teams.map((team, i) =>
      `<span class="team" style="border-color:${colourOf(team)}">${team}</span>` +
      `<span class="goals" data-team="${team}">${ref.score[i]}</span>`).join(" : ");
  }
  const state = ref.running ? "<span class='running'>playing</span>" : "<span class='stopped'>stopped</span>";
  const half = ref.half ? `half ${ref.half} · ${clock(ref.game_time)}` : "before kick-off";
  document.getElementById("clock").innerHTML = `${half} · ${state} · sim ${clock(message.t)}`;
}

let shownEvents = "";
function showEvents(events) {
  const key = events.map((e) => e.t + e.text).join("|");
  if (key === shownEvents) return;
  shownEvents = key;
  const list = document.getElementById("events");
  list.innerHTML = "";
  for (const e of events.slice().reverse()) {
    const item = document.createElement("li");
    item.textContent = `${clock(e.t)} ${e.text}`;
    list.appendChild(item);
  }
}

// ---- drawing --------------------------------------------------------------------------------------------------

let scale = 40, originX = 0, originY = 0;

function fitCanvas() {
  // the field fills what the side panel leaves of the window
  const side = document.getElementById("side");
  const width = document.querySelector("main").clientWidth - side.offsetWidth - 30;
  const height = window.innerHeight - document.getElementById("bar").offsetHeight - 24;
  canvas.width = Math.max(320, width);
  canvas.height = Math.max(220, height);
  resize();
}
window.addEventListener("resize", fitCanvas);

function resize() {
  if (!hello) return;
  const f = hello.field;
  const w = f.length + 2 * f.border + 1.4, h = f.width + 2 * f.border;
  scale = Math.min(canvas.width / w, canvas.height / h);
  originX = canvas.width / 2;
  originY = canvas.height / 2;
  fieldLayer = document.createElement("canvas");  // the markings change only with the size: drawn once
  fieldLayer.width = canvas.width;
  fieldLayer.height = canvas.height;
  const c = fieldLayer.getContext("2d");
  c.fillStyle = "#2e7d32";
  c.fillRect(0, 0, canvas.width, canvas.height);
  drawField(f, c);
  draw();
}
let fieldLayer = null;

function px(x) { return originX + x * scale; }
function py(y) { return originY - y * scale; }

function draw() {
  if (!hello) return;
  const f = hello.field;
  if (fieldLayer) ctx.drawImage(fieldLayer, 0, 0);
  if (!frame) return;
  for (const robot of frame.robots) drawPlan(robot);
  for (const robot of frame.robots) drawRobot(robot, f);
  if (frame.ball) drawBall(frame.ball, f);
  if (frame.belief) drawBelief(frame.belief, f);
}

function drawField(f, c) {
  c.strokeStyle = "#ffffff";
  c.lineWidth = Math.max(1, f.line_width * scale);
  for (const [[x0, y0], [x1, y1]] of f.segments) {
    c.beginPath();
    c.moveTo(px(x0), py(y0));
    c.lineTo(px(x1), py(y1));
    c.stroke();
  }
  for (const a of f.arcs) {
    c.beginPath();
    c.arc(px(a.x), py(a.y), a.radius * scale, -a.end, -a.start);
    c.stroke();
  }
  c.fillStyle = "#ffffff";
  for (const [x, y] of f.spots) {
    c.beginPath();
    c.arc(px(x), py(y), Math.max(2, f.spot_radius * scale), 0, 2 * Math.PI);
    c.fill();
  }
  for (const g of f.goals) {
    const [[x0, y0], [, y1]] = g.posts;
    const back = x0 + g.side * g.depth;
    c.fillStyle = "rgba(255,255,255,0.18)";
    c.fillRect(Math.min(px(x0), px(back)), Math.min(py(y0), py(y1)), Math.abs(px(back) - px(x0)),
      Math.abs(py(y1) - py(y0)));
    c.strokeStyle = "#e0e0e0";
    c.lineWidth = 3;
    c.beginPath();
    c.moveTo(px(x0), py(y0));
    c.lineTo(px(back), py(y0));
    c.lineTo(px(back), py(y1));
    c.lineTo(px(x0), py(y1));
    c.stroke();
  }
}

function drawPlan(robot) {
  const colour = colourOf(robot.team);
  if (robot.path && robot.path.length > 1) {
    ctx.strokeStyle = colour;
    ctx.globalAlpha = 0.6;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(px(robot.path[0][0]), py(robot.path[0][1]));
    for (const [x, y] of robot.path.slice(1)) ctx.lineTo(px(x), py(y));
    ctx.stroke();
    ctx.globalAlpha = 1;
  }
  if (robot.target) {
    const [tx, ty] = robot.target;
    ctx.strokeStyle = colour;
    ctx.lineWidth = 2;
    ctx.setLineDash([4, 4]);
    ctx.beginPath();
    ctx.moveTo(px(robot.x), py(robot.y));
    ctx.lineTo(px(tx), py(ty));
    ctx.stroke();
    ctx.setLineDash([]);
    const s = 5;
    ctx.beginPath();
    ctx.moveTo(px(tx) - s, py(ty) - s); ctx.lineTo(px(tx) + s, py(ty) + s);
    ctx.moveTo(px(tx) - s, py(ty) + s); ctx.lineTo(px(tx) + s, py(ty) - s);
    ctx.stroke();
  }
}

function drawRobot(robot, f) {
  const r = f.robot_radius * scale;
  const x = px(robot.x), y = py(robot.y);
  ctx.fillStyle = colourOf(robot.team);
  ctx.strokeStyle = "#101010";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  ctx.arc(x, y, r, 0, 2 * Math.PI);
  ctx.fill();
  ctx.stroke();
  ctx.strokeStyle = "#101010";
  ctx.lineWidth = 3;
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(x + Math.cos(robot.theta) * r, y - Math.sin(robot.theta) * r);
  ctx.stroke();
  ctx.fillStyle = "#101010";
  ctx.font = `bold ${Math.round(r * 0.9)}px system-ui, sans-serif`;
  ctx.textAlign = "center";
  ctx.textBaseline = "middle";
  ctx.fillText(String(robot.id), x, y);
  const role = robot.role ? ROLE_SHORT[robot.role] ?? robot.role : "";
  if (role) {
    ctx.fillStyle = "#ffffff";
    ctx.font = `${Math.round(r * 0.7)}px system-ui, sans-serif`;
    ctx.fillText(role, x, y + r + 8);
  }
}

function drawBall(ball, f) {
  const r = Math.max(4, f.ball_radius * scale);
  const high = ball.z !== null && ball.z > f.ball_radius + 0.05;
  if (high) {
    ctx.fillStyle = "rgba(0,0,0,0.35)";
    ctx.beginPath();
    ctx.arc(px(ball.x), py(ball.y), r, 0, 2 * Math.PI);
    ctx.fill();
  }
  const lift = high ? ball.z * scale * 0.5 : 0; // drawn above its shadow, by half its height
  ctx.fillStyle = "#ff9800";
  ctx.strokeStyle = "#3e2723";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  ctx.arc(px(ball.x), py(ball.y) - lift, high ? r * (1 + ball.z * 0.3) : r, 0, 2 * Math.PI);
  ctx.fill();
  ctx.stroke();
  if (high) {
    ctx.fillStyle = "#ffffff";
    ctx.font = "12px system-ui, sans-serif";
    ctx.textAlign = "left";
    ctx.fillText(`${ball.z.toFixed(1)} m`, px(ball.x) + r + 4, py(ball.y) - lift);
  }
}

function drawBelief(belief, f) {
  const team = belief.robot.replace(/[0-9]+$/, "");
  const colour = colourOf(team);
  const r = f.robot_radius * scale;
  ctx.lineWidth = 2;
  ctx.setLineDash([5, 3]);
  for (const mate of belief.teammates) {
    ctx.strokeStyle = colour;
    ctx.beginPath();
    ctx.arc(px(mate.x), py(mate.y), r * 1.15, 0, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.strokeStyle = "#ffeb3b";
  for (const [x, y] of belief.opponents) {
    ctx.beginPath();
    ctx.rect(px(x) - r, py(y) - r, 2 * r, 2 * r);
    ctx.stroke();
  }
  ctx.strokeStyle = "#bdbdbd";
  for (const [x, y] of belief.obstacles) {
    ctx.beginPath();
    ctx.arc(px(x), py(y), r * 0.5, 0, 2 * Math.PI);
    ctx.stroke();
  }
  if (belief.ball) {
    ctx.strokeStyle = "#ff9800";
    ctx.beginPath();
    ctx.arc(px(belief.ball.x), py(belief.ball.y), Math.max(7, f.ball_radius * scale * 1.6), 0, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.setLineDash([]);
}

connect();

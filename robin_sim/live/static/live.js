// The live page: draws the frames the server pushes, shows the session's status and sends the
// participant's clicks, buttons and keys. No framework, no network beyond this page's server.
"use strict";

(() => {
  const canvas = document.getElementById("scene");
  const context = canvas.getContext("2d");
  const $ = (id) => document.getElementById(id);
  const KEEP = 3000; // latencies kept for the bench and the tests

  // What the page measured; the browser tests and bench/bench_live.py read it.
  const live = {
    role: null, status: null, errors: [], connected: false, closed: null, over: false,
    frameBlock: null, // the block whose frames are drawn
    received: 0, drawn: 0, lastSeq: 0, latencies: [], receivedAt: [], drawnAt: [],
    sent: [], accepted: 0,
    listeners: [], // other scripts of the page (the experimenter's view) get every message
  };
  window.robinLive = live;

  // --- the WebSocket: reconnects by itself -----------------------------------------------------
  // A lost connection is not the end: the session runs on in the server, and the page comes
  // back with the same address (and token), after 0.5, 1, 2, 4, then every 8 s, and takes its
  // place again. Only a session that is over stays closed.
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  const address = `${scheme}//${location.host}/ws${location.search}`;
  const BACKOFF_MS = [500, 1000, 2000, 4000, 8000];
  live.reconnects = 0; // times the page came back (read by the tests)
  live.attempts = 0; // tries since the connection was lost
  let socket = null;

  function connect() {
    socket = new WebSocket(address);
    socket.binaryType = "arraybuffer";
    socket.onopen = () => {
      if (live.closed) live.reconnects += 1;
      live.connected = true;
      live.closed = null;
      live.attempts = 0;
      clearError();
    };
    socket.onclose = (event) => {
      const wasOpen = live.connected;
      live.connected = false;
      if (wasOpen || !live.closed) live.closed = { code: event.code, reason: event.reason };
      live.lastClose = { code: event.code, reason: event.reason }; // kept after a reconnect
      // over: the last status said so, or the server said goodbye (1001) at the run's end
      const over = (!!live.status && live.status.phase === "done") || event.code === 1001;
      live.over = over;
      setRole(live.role, true, over);
      updateControls();
      if (over) return;
      const wait = BACKOFF_MS[Math.min(live.attempts, BACKOFF_MS.length - 1)];
      live.attempts += 1;
      showError(`The connection to Robin was lost: reconnecting (try ${live.attempts})… ` +
        "If this lasts, please tell the experimenter.");
      setTimeout(connect, wait);
    };
    socket.onmessage = (event) => {
      if (typeof event.data === "string") {
        textMessage(JSON.parse(event.data));
      } else {
        frameMessage(event.data);
      }
    };
  }
  live.dropConnection = () => socket && socket.close(4000, "dropped by a test"); // tests only

  function send(message) {
    if (!socket || socket.readyState !== WebSocket.OPEN) return false;
    socket.send(JSON.stringify(message));
    live.sent.push(message);
    return true;
  }
  live.send = send;
  live.showError = (text) => showError(text);
  // The webcam's readings (many a second) go out without being kept in live.sent.
  live.sendReading = (message) => {
    if (!socket || socket.readyState !== WebSocket.OPEN) return false;
    socket.send(JSON.stringify(message));
    return true;
  };

  function textMessage(message) {
    for (const listener of live.listeners) listener(message);
    if (message.type === "status") {
      if (message.block_number != null && message.block_number !== live.frameBlock &&
          message.phase !== "done") {
        newBlock(message.block_number); // before the new block's first frame arrives
      }
      live.status = message;
      showStatus(message);
    } else if (message.type === "error") {
      live.errors.push(message.message);
      showError(message.message);
      const questions = $("q-error");
      if (live.status && live.status.phase === "questionnaire" && questions) {
        questions.textContent = message.message;
      }
    } else if (message.type === "role") {
      setRole(message.role, false);
    }
  }

  // --- frames: [4-byte header length][JSON header][JPEG] ------------------------------------
  let pending = null;
  let drawScheduled = false;

  function frameMessage(buffer) {
    const length = new DataView(buffer).getUint32(0);
    const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
    if (header.block !== live.frameBlock) newBlock(header.block); // its frames count from 1
    const blob = new Blob([new Uint8Array(buffer, 4 + length)], { type: "image/jpeg" });
    live.received += 1;
    live.receivedAt.push(performance.now());
    createImageBitmap(blob).then((bitmap) => {
      if (header.seq <= live.lastSeq || (pending && header.seq <= pending.header.seq)) {
        bitmap.close(); // an older frame decoded late: the newer one is shown
        return;
      }
      if (pending) pending.bitmap.close();
      pending = { bitmap, header };
      if (!drawScheduled) {
        drawScheduled = true;
        requestAnimationFrame(draw);
      }
    }, () => showError("a frame could not be decoded"));
  }

  // A new block's session: its frames are numbered from 1 again, and the last block's image
  // must not stand for it.
  function newBlock(block) {
    live.frameBlock = block;
    live.lastSeq = 0;
    if (pending) pending.bitmap.close();
    pending = null;
    context.fillStyle = "#000";
    context.fillRect(0, 0, canvas.width, canvas.height);
  }

  function draw() {
    drawScheduled = false;
    if (!pending) return;
    const { bitmap, header } = pending;
    pending = null;
    context.drawImage(bitmap, 0, 0, canvas.width, canvas.height);
    bitmap.close();
    live.drawn += 1;
    live.lastSeq = header.seq;
    live.drawnAt.push(performance.now());
    live.latencies.push(Date.now() - header.captured_ms); // same clock: server and page
    if (live.latencies.length > KEEP) live.latencies.splice(0, live.latencies.length - KEEP);
  }

  // --- the status ----------------------------------------------------------------------------
  // The screens between sessions, by phase (no robot input is taken on them).
  const SCREENS = {
    instructions: "Instructions", questionnaire: "Questionnaire", consent: "Consent",
    debrief: "Debrief",
  };

  function showStatus(status) {
    const turn = $("turn");
    const done = status.phase === "done";
    const screen = SCREENS[status.phase];
    turn.className = `turn ${done || screen ? "" : status.turn}`;
    turn.textContent = done ? `Session over (${status.status})`
      : status.phase === "instructions" && status.practice ? "Practice"
      : screen || (status.turn === "robot" ? "Robin's turn" : "Your turn");
    $("doing").textContent = status.robot_doing || "—";
    $("message").textContent = status.message || "";
    showStream(status.stream, done);
    const notice = $("notice"); // what Robin took as OK, or why it handed the step back
    if (notice) notice.textContent = status.phase === "done" ? "" : status.notice || "";
    showGuide(done ? null : status.guide, status.phase, status.feedback_left_s);
    showClicked(status.clicked);
    const takeBackLeft = $("take-back-left"); // seconds left to take back what stood last
    if (takeBackLeft) {
      takeBackLeft.textContent = status.take_back_left_s == null ? ""
        : ` ${Math.ceil(status.take_back_left_s)} s`;
    }
    if ((status.inputs_accepted || 0) > live.accepted) clearError(); // a valid input came
    live.accepted = status.inputs_accepted || 0;
    $("legs").textContent = status.legs_total == null ? "—"
      : `${status.legs_delivered} / ${status.legs_total}`;
    $("gestures").textContent = status.gestures;
    $("actions").textContent = status.actions;
    $("simtime").textContent = `${Number(status.sim_time || 0).toFixed(1)} s`;
    $("who").textContent = `participant ${status.participant}` +
      (status.blocks > 1 ? ` · block ${status.block_number} of ${status.blocks}` : "");
    showPolicy(status.policy);
    showScreen(status);
    if (window.robinQuestionnaire) window.robinQuestionnaire.show(status);
    if (window.robinScreens) window.robinScreens.show(status);
    updateControls();
  }

  // The handover in plain words: the goal, the next step, all steps as a checklist, the legend.
  function showGuide(guide, phase, left) {
    const list = $("checklist");
    if (!guide) {
      $("goal").textContent = "";
      $("instruction").textContent = "";
      list.replaceChildren();
      $("legend").replaceChildren();
      return;
    }
    $("goal").textContent = `Leg ${guide.handover_number} of ${guide.handovers}: ${guide.goal}`;
    $("instruction").textContent = phase === "waiting_for_gesture" ? guide.instruction
      : phase === "waiting_for_thumb" ? "Thumb up if Robin did what you meant, thumb down if not." +
        (left == null ? "" : ` ${Math.ceil(left)} s left; no thumb counts as OK.`)
      : "Watch Robin: thumb down stops a wrong move.";
    list.replaceChildren(...guide.checklist.map((step, k) => {
      const item = document.createElement("li");
      item.textContent = step.text;
      item.className = step.done ? "done" : k === guide.step ? "current" : "";
      return item;
    }));
    const legs = guide.legs.map((leg) => {
      const chip = document.createElement("span");
      chip.className = leg.delivered ? "chip delivered" : "chip";
      chip.style.setProperty("--leg", leg.css);
      chip.textContent = `leg ${leg.number} ${leg.colour}`;
      return chip;
    });
    const spots = document.createElement("span");
    spots.className = "chip spot";
    spots.textContent = `spots 1-${guide.spots}: the rings`;
    $("legend").replaceChildren(...legs, spots);
  }

  // A busy machine lowers the image first (robin_sim.live.quality): the page says so.
  function showStream(stream, done) {
    const note = $("stream-note");
    if (!note) return;
    note.textContent = done || !stream || !stream.lowered ? ""
      : `The computer is busy: Robin's image comes at ${stream.fps} frames a second` +
        (stream.inset ? "" : ", without its eye view") +
        ". Robin may also move more slowly than usual.";
  }

  // A ring around what was clicked last, in frame pixels scaled to the shown canvas.
  function showClicked(clicked) {
    const ring = $("target-ring");
    if (!clicked) {
      ring.hidden = true;
      return;
    }
    ring.hidden = false;
    ring.style.left = `${(clicked.x / canvas.width) * 100}%`;
    ring.style.top = `${(clicked.y / canvas.height) * 100}%`;
    ring.title = `you pointed at ${clicked.name}`;
    ring.dataset.target = `${clicked.kind} ${clicked.number}`;
  }

  function showPolicy(policy) {
    const box = $("policy");
    if (!policy || !policy.actions) {
      $("policy-state").textContent = "no decision yet";
      box.replaceChildren();
      return;
    }
    $("policy-state").textContent = `state: ${policy.state}`;
    const entries = Object.entries(policy.actions);
    const best = Math.max(...entries.map(([, p]) => p));
    const unique = entries.filter(([, p]) => p === best).length === 1; // a clear favourite
    box.replaceChildren(...entries.map(([action, p]) => {
      const row = document.createElement("div");
      row.className = unique && p === best ? "row best" : "row";
      row.dataset.action = action;
      const name = document.createElement("span");
      name.textContent = action;
      const bar = document.createElement("div");
      bar.className = "bar";
      const fill = document.createElement("div");
      fill.className = "fill";
      fill.style.width = `${Math.max(0, Math.min(1, p)) * 100}%`;
      bar.append(fill);
      const value = document.createElement("span");
      value.className = "p";
      value.textContent = p.toFixed(2);
      row.append(name, bar, value);
      return row;
    }));
  }

  function showScreen(status) {
    const screen = $("screen");
    screen.className = "screen";
    if (status.phase === "instructions") {
      screen.hidden = false;
      $("screen-title").textContent = status.practice ? "Practice"
        : status.blocks > 1 ? `Block ${status.block_number} of ${status.blocks}` : "Instructions";
      $("screen-text").textContent = status.starting ? "Starting…"
        : status.instructions || status.message || "";
      $("start").hidden = live.role !== "control" || !!status.starting;
    } else if (status.phase === "done" && status.status === "declined") {
      screen.hidden = false;
      $("screen-title").textContent = "Thank you";
      $("screen-text").textContent = "You did not agree to take part: nothing is kept but " +
        "that answer. You can close this tab.";
      $("start").hidden = true;
    } else if (status.phase === "done") {
      const normal = ["finished", "ended", "capped"].includes(status.status);
      screen.hidden = false;
      screen.className = normal ? "screen finished" : "screen";
      $("screen-title").textContent = normal ? "Session finished"
        : `Session saved (${status.status})`;
      $("screen-text").textContent = (normal ? "Thank you! " : "") +
        `${status.legs_delivered} of ${status.legs_total ?? "?"} legs delivered. ` +
        "You can close this tab.";
      $("start").hidden = true;
    } else {
      screen.hidden = true;
    }
  }

  function setRole(role, closed, over) {
    live.role = role;
    const badge = $("role");
    badge.className = `badge ${over ? "finished" : closed ? "closed" : role}`;
    badge.textContent = over ? "session finished" : closed ? "reconnecting…"
      : role === "control" ? "you control this session"
      : role === "experimenter" ? "experimenter" : "watching (read-only)";
    updateControls();
  }

  function updateControls() {
    const running = live.status && !SCREENS[live.status.phase] && live.status.phase !== "done";
    const usable = live.connected && live.role === "control";
    for (const button of document.querySelectorAll("#controls button")) {
      button.disabled = !(usable && running);
    }
  }

  // An error stays next to the image until the next input the session takes.
  function showError(text) {
    $("error").textContent = text;
  }
  function clearError() {
    $("error").textContent = "";
  }

  // --- the participant's inputs --------------------------------------------------------------
  const ACTIONS = {
    up: () => send({ type: "thumb", value: "up" }),
    down: () => send({ type: "thumb", value: "down" }),
    end: () => confirm("End this session? It is saved as it stands.") && send({ type: "end" }),
    start: () => send({ type: "start" }),
  };
  const KEYS = {
    u: "up", ArrowUp: "up", d: "down", ArrowDown: "down", e: "end", Enter: "start", s: "start",
  };
  // the gesture keys a message may name, their labels and shortcuts come from the Python
  // source (inputs.GESTURE_KEYS, inputs.GESTURE_SHORTCUTS, types.sign_label)
  const PAGE = JSON.parse(document.body.dataset.constants);
  const gestureButtons = $("gesture-buttons");
  for (const gesture of PAGE.gestures) {
    ACTIONS[gesture] = () => send({ type: "gesture", gesture });
    const shortcut = PAGE.shortcuts[gesture];
    KEYS[shortcut] = gesture;
    if (gestureButtons) {
      const button = document.createElement("button");
      const label = PAGE.signs[gesture];
      button.type = "button";
      button.dataset.send = gesture;
      button.append(label.charAt(0).toUpperCase() + label.slice(1) + " ");
      const kbd = document.createElement("kbd");
      kbd.textContent = shortcut.toUpperCase();
      button.append(kbd);
      gestureButtons.append(button);
    }
  }

  // The take-back button: takes back Robin's last action that stood, within its window (the label,
  // key and window from the Python source: inputs.TAKE_BACK_*, take_back.TAKE_BACK_WINDOW_S)
  const TAKE_BACK = PAGE.take_back;
  ACTIONS.take_back = () => send({ type: "take_back" });
  KEYS[TAKE_BACK.key] = "take_back";
  const takeBackSlot = $("take-back-button");
  if (takeBackSlot) {
    const button = document.createElement("button");
    button.type = "button";
    button.id = "take-back";
    button.className = "take-back";
    button.dataset.send = "take_back";
    button.title = `Takes back Robin's last action that stood (thumb up or no thumb), for ` +
      `${TAKE_BACK.window_s} s after it stood, while it is your turn.`;
    button.append(`${TAKE_BACK.label} `);
    const kbd = document.createElement("kbd");
    kbd.textContent = TAKE_BACK.key.toUpperCase();
    const left = document.createElement("span");
    left.id = "take-back-left";
    left.className = "left";
    button.append(kbd, left);
    takeBackSlot.append(button);
  }

  for (const button of document.querySelectorAll("button[data-send]")) {
    button.addEventListener("click", () => ACTIONS[button.dataset.send]());
  }
  document.addEventListener("keydown", (event) => {
    if (event.ctrlKey || event.altKey || event.metaKey || event.repeat) return;
    const name = KEYS[event.key.length === 1 ? event.key.toLowerCase() : event.key];
    if (!name || live.role !== "control") return;
    const phase = live.status ? live.status.phase : null;
    // a form or a screen's buttons take their own keys (typing an "e" is no End)
    if (phase !== "instructions" && SCREENS[phase]) return;
    if (event.target.closest && event.target.closest("input, textarea, select")) return;
    if ((name === "start") !== (phase === "instructions")) return;
    event.preventDefault();
    ACTIONS[name]();
  });

  // Closing or reloading the controlling tab ends the session (saved as "closed"): ask first.
  window.addEventListener("beforeunload", (event) => {
    const phase = live.status ? live.status.phase : "done";
    if (live.role === "control" && live.connected && phase !== "done") event.preventDefault();
  });

  // A click points: the pixel in the frame's coordinates, whatever size the canvas is shown at.
  canvas.addEventListener("click", (event) => {
    if (live.role !== "control") {
      if (live.role !== "experimenter") showError("this tab watches read-only");
      return;
    }
    const box = canvas.getBoundingClientRect();
    const x = Math.floor(((event.clientX - box.left) / box.width) * canvas.width);
    const y = Math.floor(((event.clientY - box.top) / box.height) * canvas.height);
    send({
      type: "point",
      x: Math.min(canvas.width - 1, Math.max(0, x)),
      y: Math.min(canvas.height - 1, Math.max(0, y)),
    });
  });
  connect();
})();

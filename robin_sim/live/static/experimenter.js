// The experimenter's view: the participant's page (live.js) plus the stream's and the pacer's
// figures, the log as it grows, and the run's controls (pause, resume, next block, end, notes).
"use strict";

(() => {
  const live = window.robinLive;
  const $ = (id) => document.getElementById(id);
  const view = { last: null, replies: [] };
  live.experimenter = view; // read by the browser tests

  live.listeners.push((message) => {
    if (message.type === "status" && message.participant_page) {
      const page = message.participant_page;
      $("page-state").textContent = page.connected
        ? `connected${page.returns ? ` (came back ${page.returns}×)` : ""}`
        : page.away_s == null ? "not connected yet"
        : `away ${text(page.away_s)} s: the session holds; saved closed after ${page.grace_s} s`;
    }
    if (message.type === "experimenter") {
      view.last = message;
      showView(message);
    } else if (message.type === "done") {
      view.replies.push(message);
      $("reply").textContent = message.command === "note" ? "" : `${message.command}: done`;
      $("reply").className = "reply done"; // a command carried out is no error
      if (message.command === "note" && message.note) {
        $("note-saved").textContent = `note saved at ${message.note.utc}`;
        $("note-text").value = "";
      }
    } else if (message.type === "error") {
      $("reply").textContent = message.message;
      $("reply").className = "reply refused";
    }
  });

  function text(value, digits = 1) {
    return value == null ? "—" : Number(value).toFixed(digits);
  }

  // A study block's caps: what is used of each, and what was reached.
  function limitsText(limits) {
    if (!limits) return "none";
    const parts = [];
    if (limits.block_seconds != null) {
      parts.push(`time ${text(limits.sim_time)} / ${limits.block_seconds} s`);
    }
    if (limits.block_actions != null) parts.push(`actions ${limits.actions} / ${limits.block_actions}`);
    if (limits.inactivity_seconds != null) {
      parts.push(limits.inactive ? "participant INACTIVE: the session holds"
        : `inactivity after ${limits.inactivity_seconds} s`);
    }
    if (limits.reached) parts.push(`REACHED: ${limits.reached} (the block ends)`);
    return parts.join("; ") || "none";
  }

  function showView(message) {
    const pacing = message.pacing;
    $("run-phase").textContent = `run: ${message.run_phase}`;
    $("folder").textContent = `session folder: ${message.session_folder}`;
    if (pacing) {
      $("stream-fps").textContent = text(pacing.stream_fps);
      $("publish-latency").textContent = pacing.latency_ms
        ? `${text(pacing.latency_ms.median, 0)} / ${text(pacing.latency_ms.p95, 0)} ms` : "—";
      $("frame-ms").textContent = text(pacing.frame_ms);
      $("behind").textContent = `${text(pacing.behind_s, 2)}, ${pacing.slips ?? "—"}`;
      $("speed").textContent = `${pacing.speed}x, ${pacing.paused ? "paused" : "running"}`;
    }
    $("limits").textContent = limitsText(message.limits);
    $("limits").className = message.limits && (message.limits.reached || message.limits.inactive)
      ? "reached" : "";
    $("events").replaceChildren(...(message.events || []).map((event) => {
      const item = document.createElement("li");
      const { wall, event: kind, sim_time: at, ...rest } = event;
      const detail = Object.entries(rest).map(([k, v]) => `${k} ${JSON.stringify(v)}`).join(", ");
      item.textContent = `${text(at)} s ${kind}${detail ? `: ${detail}` : ""}`;
      item.dataset.event = kind;
      return item;
    }));
    $("tabs").textContent = message.tabs.map((t) => `${t.role} (${t.frames_dropped})`)
      .join(", ");
    const rows = message.log.map((step) => {
      const row = document.createElement("tr");
      const target = step.target ? `${step.target.kind} ${step.target.index + 1}` : "";
      for (const cell of [step.t, (step.handover ?? 0) + 1, step.true_gesture || "",
        step.action || "(repeat)", target,
        (step.feedback || "") + (step.taken_back ? " (taken back)" : ""), step.legs_delivered,
        text(step.sim_time)]) {
        const td = document.createElement("td");
        td.textContent = cell;
        row.append(td);
      }
      return row;
    });
    $("log").tBodies[0].replaceChildren(...rows);
  }

  // Frame rate and latency of this tab, once a second (the participant's page shows none).
  function perSecond(times, now) {
    while (times.length && now - times[0] > 2000) times.shift();
    return times.length / 2;
  }
  function quantile(values, q) {
    const sorted = [...values].sort((a, b) => a - b);
    return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
  }
  setInterval(() => {
    const now = performance.now();
    $("fps-in").textContent = perSecond(live.receivedAt, now).toFixed(1);
    $("fps-drawn").textContent = perSecond(live.drawnAt, now).toFixed(1);
    const recent = live.latencies.slice(-60);
    $("latency").textContent = recent.length
      ? `${quantile(recent, 0.5).toFixed(0)} / ${quantile(recent, 0.95).toFixed(0)} ms` : "—";
  }, 1000);

  for (const button of document.querySelectorAll("button[data-command]")) {
    button.addEventListener("click", () => {
      const command = button.dataset.command;
      if (command === "end" && !confirm("End the whole run? The session is saved as ended.")) {
        return;
      }
      live.send({ type: command });
    });
  }
  $("note-save").addEventListener("click", () => {
    const note = $("note-text").value.trim();
    if (note) live.send({ type: "note", text: note });
  });
})();

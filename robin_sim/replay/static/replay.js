// The replay page: a frame of the recorded run for each position of the timeline, with what
// happened when (steps, gestures, thumbs, notes, events, questionnaires) marked on a track and
// listed below; a marker, a row or "Go to step" jumps there.
"use strict";

(async () => {
  const $ = (id) => document.getElementById(id);
  const meta = await (await fetch("/meta")).json();
  const annotations = await (await fetch("/events")).json();
  const image = $("frame");
  const timeline = $("timeline");
  const state = { meta, annotations, shown: -1, wanted: 0, loading: false, playing: false };
  window.robinReplay = state;
  timeline.max = String(meta.frames - 1);
  const duration = Math.max(meta.times[meta.frames - 1], 1e-9);

  // The recorded frame nearest ``time`` seconds (a lowered live stream records fewer frames,
  // so the nearest may be seconds away: the page then says how far).
  function frameAt(time) {
    let low = 0, high = meta.frames - 1;
    while (low < high) {
      const mid = (low + high) >> 1;
      if (meta.times[mid] < time - 1e-6) low = mid + 1; else high = mid;
    }
    if (low > 0 && time - meta.times[low - 1] < meta.times[low] - time) low -= 1;
    return low;
  }

  function jumpTo(time) {
    state.playing = false;
    $("play").textContent = "Play";
    state.wanted = frameAt(time);
    timeline.value = String(state.wanted);
    load();
  }
  state.jumpTo = jumpTo;

  function jumpToStep(step) {
    const found = annotations.steps.find((s) => s.step === step);
    if (!found) {
      $("shown-step").textContent = `no step ${step} (steps 1-${annotations.steps.length})`;
      return false;
    }
    state.step = step;
    const shown = meta.times[frameAt(found.time)];
    const off = shown - found.time;
    let text = `step ${step} at ${found.time.toFixed(2)} s`;
    if (Math.abs(off) > 0.5 / meta.fps) {
      const side = off > 0 ? "later" : "earlier";
      text += ` (no frame recorded then: the nearest, ${shown.toFixed(2)} s, is ` +
        `${Math.abs(off).toFixed(2)} s ${side})`;
    }
    $("shown-step").textContent = text;
    jumpTo(found.time);
    return true;
  }
  state.jumpToStep = jumpToStep;

  const rows = annotations.markers.map((m) => {
    const mark = document.createElement("button");
    mark.type = "button";
    mark.className = `mark ${m.kind}`;
    mark.style.left = `${(m.time / duration) * 100}%`;
    mark.title = `${m.time.toFixed(2)} s: ${m.label}`;
    mark.addEventListener("click", () => jumpTo(m.time));
    $("marks").append(mark);
    const row = document.createElement("tr");
    row.dataset.kind = m.kind;
    row.tabIndex = 0;
    for (const text of [`${m.time.toFixed(2)} s`, m.kind, m.label]) {
      const cell = document.createElement("td");
      cell.textContent = text;
      row.append(cell);
    }
    const go = () => (m.step != null ? jumpToStep(m.step) : jumpTo(m.time));
    row.addEventListener("click", go);
    row.addEventListener("keydown", (event) => { if (event.key === "Enter") go(); });
    return [m, row];
  });
  $("events").tBodies[0].replaceChildren(...rows.map(([, row]) => row));
  $("step").max = String(Math.max(1, annotations.steps.length));

  function highlight(time) {
    for (const [m, row] of rows) row.classList.toggle("here", Math.abs(m.time - time) < 0.05);
  }

  function load() {
    if (state.loading || state.wanted === state.shown) return;
    state.loading = true;
    const index = state.wanted;
    image.onload = () => {
      state.loading = false;
      state.shown = index;
      $("time").textContent = `${meta.times[index].toFixed(2)} s`;
      highlight(meta.times[index]);
      if (state.playing) {
        timeline.value = String(index);
        state.wanted = Math.min(meta.frames - 1, index + 1);
        if (state.wanted === index) {
          state.playing = false;
          $("play").textContent = "Play";
        }
      }
      load();
    };
    image.onerror = () => { state.loading = false; };
    image.src = `/frame/${index}`;
  }
  timeline.addEventListener("input", () => {
    state.wanted = Number(timeline.value);
    load();
  });
  $("play").addEventListener("click", () => {
    state.playing = !state.playing;
    $("play").textContent = state.playing ? "Pause" : "Play";
    if (state.playing) {
      state.wanted = Math.min(meta.frames - 1, state.shown + 1);
      load();
    }
  });
  $("go").addEventListener("click", () => jumpToStep(Number($("step").value)));
  $("step").addEventListener("keydown", (event) => {
    if (event.key === "Enter") jumpToStep(Number($("step").value));
  });
  load();
})();

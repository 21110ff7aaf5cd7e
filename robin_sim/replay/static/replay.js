// The replay page: a frame of the recorded run for each position of the timeline.
"use strict";

(async () => {
  const $ = (id) => document.getElementById(id);
  const meta = await (await fetch("/meta")).json();
  const image = $("frame");
  const timeline = $("timeline");
  const state = { meta, shown: -1, wanted: 0, loading: false, playing: false };
  window.robinReplay = state;
  timeline.max = String(meta.frames - 1);

  function load() {
    if (state.loading || state.wanted === state.shown) return;
    state.loading = true;
    const index = state.wanted;
    image.onload = () => {
      state.loading = false;
      state.shown = index;
      $("time").textContent = `${meta.times[index].toFixed(2)} s`;
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
  load();
})();

// --webcam: the participant's own hand. The page asks for the camera, shows a small mirrored
// self-view with the tracked hand drawn, runs the hand tracker (MediaPipe Hands, served by this
// page's server) and sends each reading's 21 landmarks, handedness and score over the
// WebSocket, at most 15 a second. No frame leaves the browser. A denied or missing camera falls
// back to the buttons and keys, with a plain message. window.robinLive.webcam records it all.
"use strict";

(() => {
  if (document.body.dataset.webcam !== "on") return;
  const live = window.robinLive;
  const $ = (id) => document.getElementById(id);
  const MIN_INTERVAL_MS = 1000 / 15; // at most 15 readings a second
  const TRACKING_GAP_MS = 400; // a longer gap between frames starts the tracker afresh (below)
  const KEEP = 500;
  const BONES = [[0, 1], [1, 2], [2, 3], [3, 4], [0, 5], [5, 6], [6, 7], [7, 8], [5, 9],
    [9, 10], [10, 11], [11, 12], [9, 13], [13, 14], [14, 15], [15, 16], [13, 17], [0, 17],
    [17, 18], [18, 19], [19, 20]];
  const CONSTANTS = JSON.parse(document.body.dataset.constants); // from the Python source
  const NAMES = CONSTANTS.signs; // each sign's name -> its label
  const cam = {
    state: "starting", message: "", readings: 0, found: 0, sentAt: [], replies: [],
    last: null, ready: false, readMs: [], // how long each reading held the page's thread
  };
  live.webcam = cam;
  const video = $("camera");
  const overlay = $("camera-hand");
  const draw = overlay.getContext("2d");
  $("webcam").hidden = false;

  function setState(state, message) {
    cam.state = state;
    cam.message = message;
    const shown = $("camera-state");
    shown.textContent = message;
    shown.className = state === "fallback" ? "camera-state fallback" : "camera-state";
  }

  function fallback(why) {
    setState("fallback", `${why} Use the buttons and keys instead.`);
  }

  // --- the tracker and the camera -----------------------------------------------------------
  let hands = null;
  let busy = false;
  let lastSent = 0;

  function loadTracker() {
    const script = document.createElement("script");
    script.src = `/static/vendor/hands.js${location.search}`;
    script.onload = startTracker;
    script.onerror = () => fallback("The hand tracker could not be loaded.");
    document.head.append(script);
  }

  async function startTracker() {
    hands = new window.Hands({ locateFile: (file) => `/static/vendor/${file}${location.search}` });
    hands.setOptions({
      maxNumHands: 1, modelComplexity: 1, minDetectionConfidence: 0.5,
      minTrackingConfidence: 0.5, selfieMode: false,
    });
    hands.onResults(results);
    try {
      await hands.initialize();
    } catch (error) {
      fallback(`The hand tracker did not start (${error}).`);
      return;
    }
    cam.ready = true;
    setState("running", "Camera on: show your hand.");
    setTimeout(tick, 0);
  }

  async function startCamera() {
    if (!navigator.mediaDevices || !navigator.mediaDevices.getUserMedia) {
      fallback("This page cannot use a camera here (open it as http://127.0.0.1 or https).");
      return;
    }
    try {
      video.srcObject = await navigator.mediaDevices.getUserMedia({
        video: { width: 640, height: 480 }, audio: false,
      });
      await video.play();
    } catch (error) {
      const denied = error && error.name === "NotAllowedError";
      fallback(denied ? "Camera access was denied." : "No camera was found.");
      return;
    }
    setState("loading", "Camera on; loading the hand tracker…");
    loadTracker();
  }

  function running() {
    const s = live.status;
    return live.connected && live.role === "control" && !!s && live.drawn > 0 &&
      !["instructions", "questionnaire", "done"].includes(s.phase);
  }

  async function tick() {
    if (live.over) return; // the session is over (a lost connection comes back: go on)
    const now = performance.now();
    let rest = 10; // ms until the next look
    if (!busy && running() && video.readyState >= 2 && now - lastSent >= MIN_INTERVAL_MS) {
      busy = true;
      // Tracking carries the last frame's hand into the next; after a long gap (a slow
      // machine: headless software rendering reads about one frame a second) the hand has
      // moved on and the tracker can lock onto a wrong finger layout (a thumb up read as
      // pointing for minutes), so it starts from the palm detector again.
      if (now - lastSent > TRACKING_GAP_MS) hands.reset();
      lastSent = now;
      try {
        await hands.send({ image: video });
      } catch (error) {
        fallback(`The hand tracker stopped (${error}).`);
        return;
      } finally {
        busy = false;
      }
      // the tracker runs on the page's own thread: on a slow machine it gets at most half of
      // it, so clicks, keys and the scene stay responsive between readings
      const took = performance.now() - now;
      cam.readMs.push(took);
      if (cam.readMs.length > KEEP) cam.readMs.shift();
      rest = Math.max(rest, took);
    }
    setTimeout(tick, rest);
  }

  const round = (value, places) => Number(value.toFixed(places));

  function results(result) {
    const marks = result.multiHandLandmarks && result.multiHandLandmarks[0];
    const side = result.multiHandedness && result.multiHandedness[0];
    const aspect = video.videoWidth && video.videoHeight ? video.videoWidth / video.videoHeight
      : 4 / 3;
    const message = {
      type: "hand",
      landmarks: marks ? marks.map((p) => [round(p.x, 5), round(p.y, 5), round(p.z, 5)]) : null,
      handedness: marks && side ? side.label : null,
      score: marks && side ? round(side.score, 4) : 0,
      aspect: round(Math.min(4, Math.max(0.25, aspect)), 4),
    };
    drawHand(marks);
    if (!marks || !side) message.handedness = null;
    if (message.landmarks && !message.handedness) message.landmarks = null;
    if (live.sendReading(message)) {
      cam.readings += 1;
      cam.found += message.landmarks ? 1 : 0;
      cam.sentAt.push(performance.now());
      if (cam.sentAt.length > KEEP) cam.sentAt.splice(0, cam.sentAt.length - KEEP);
    }
  }

  function drawHand(marks) {
    draw.clearRect(0, 0, overlay.width, overlay.height);
    if (!marks) return;
    const x = (p) => p.x * overlay.width;
    const y = (p) => p.y * overlay.height;
    draw.strokeStyle = "#48bb78";
    draw.lineWidth = 2;
    for (const [a, b] of BONES) {
      draw.beginPath();
      draw.moveTo(x(marks[a]), y(marks[a]));
      draw.lineTo(x(marks[b]), y(marks[b]));
      draw.stroke();
    }
    draw.fillStyle = "#f56565";
    for (const p of marks) {
      draw.beginPath();
      draw.arc(x(p), y(p), 3, 0, 2 * Math.PI);
      draw.fill();
    }
  }

  // --- what the server read -----------------------------------------------------------------
  function reading(reply) {
    cam.last = reply;
    cam.replies.push(reply);
    if (cam.replies.length > KEEP) cam.replies.splice(0, cam.replies.length - KEEP);
    const shown = !reply.found ? "no hand"
      : reply.source === "calibration" ? "calibrating"
      : reply.discarded ? `${NAMES[reply.label] || "?"} (unsure: ${reply.confidence.toFixed(2)})`
      : `${NAMES[reply.label]} ${reply.confidence.toFixed(2)}`;
    $("reading").textContent = reply.acted ? `${shown} → ${reply.acted}` : shown;
    showCursor(reply.cursor, reply.dwell);
    showCalibration(reply.calibration);
    if (reply.problem && reply.decided === CONSTANTS.cursor) live.showError?.(reply.problem);
  }

  // The fingertip cursor over the scene, with its dwell ring growing until it selects.
  function showCursor(cursor, dwell) {
    const ring = $("cursor");
    if (!cursor) {
      ring.hidden = true;
      return;
    }
    const canvas = $("scene");
    ring.hidden = false;
    ring.style.left = `${(cursor[0] / canvas.width) * 100}%`;
    ring.style.top = `${(cursor[1] / canvas.height) * 100}%`;
    $("dwell").style.transform = `scale(${Math.max(0, Math.min(1, dwell))})`;
  }

  function showCalibration(calibration) {
    const box = $("calibration");
    if (!calibration || !calibration.calibrating) {
      box.hidden = true;
      return;
    }
    box.hidden = false;
    $("calibration-ask").textContent = calibration.instruction;
    const done = calibration.done.length;
    $("calibration-done").textContent = `${done} of ${calibration.order.length} done` +
      (calibration.note ? `: ${calibration.note}` : "");
  }

  live.listeners.push((message) => {
    if (message.type === "reading") reading(message);
    else if (message.type === "status" && message.webcam) {
      showCalibration(message.webcam.calibration);
    }
  });
  $("calibration-skip").addEventListener("click", () => {
    live.send({ type: "calibration", action: "skip" });
  });

  // Only the controlling tab uses the camera (watchers and the experimenter never do).
  function whenControlling() {
    if (live.role === "control") startCamera();
    else if (live.role === null && !live.over) setTimeout(whenControlling, 50);
    else setState("off", "Camera off: this tab watches.");
  }
  whenControlling();
})();

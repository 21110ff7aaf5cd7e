// Runs the vendored hand tracker on frames handed in by make_data.py (one at a time, in order,
// as a video would give them); the same options as the live page's webcam.js.
"use strict";
(() => {
  const canvas = document.getElementById("frame");
  const context = canvas.getContext("2d");
  const hands = new Hands({ locateFile: (file) => `/static/vendor/${file}` });
  hands.setOptions({
    maxNumHands: 1, modelComplexity: 1, minDetectionConfidence: 0.5,
    minTrackingConfidence: 0.5, selfieMode: false,
  });
  let last = null;
  hands.onResults((results) => { last = results; });
  window.harness = { ready: false, error: null };
  hands.initialize().then(() => { window.harness.ready = true; },
    (error) => { window.harness.error = String(error); });
  window.harness.reset = () => hands.reset();
  window.harness.read = async (url) => {
    const image = new Image();
    image.src = url;
    await image.decode();
    canvas.width = image.width;
    canvas.height = image.height;
    context.drawImage(image, 0, 0);
    last = null;
    await hands.send({ image: canvas });
    const marks = last && last.multiHandLandmarks && last.multiHandLandmarks[0];
    const side = last && last.multiHandedness && last.multiHandedness[0];
    return {
      landmarks: marks ? marks.map((p) => [p.x, p.y, p.z]) : null,
      handedness: side ? side.label : null,
      score: side ? side.score : 0,
    };
  };
})();

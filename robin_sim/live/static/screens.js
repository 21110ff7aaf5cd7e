// A study's consent and debrief screens (phases "consent" and "debrief"): the text from the
// status, and buttons that send {"type": "consent", "value": "agree" | "decline"} or
// {"type": "finish"}. The first button takes the focus: Tab moves, Enter or Space presses.
"use strict";

(() => {
  const $ = (id) => document.getElementById(id);
  let shown = null;

  function show(status) {
    const box = $("page-screen");
    const screen = status.phase === "consent" ? status.consent
      : status.phase === "debrief" ? status.debrief : null;
    if (!screen) {
      box.hidden = true;
      shown = null;
      return;
    }
    box.hidden = false;
    const control = window.robinLive.role === "control";
    for (const id of ["ps-agree", "ps-decline", "ps-finish"]) $(id).disabled = !control;
    if (shown === status.phase) return;
    shown = status.phase;
    $("ps-title").textContent = screen.title;
    $("ps-text").textContent = screen.text;
    const consent = status.phase === "consent";
    $("ps-agree").hidden = $("ps-decline").hidden = !consent;
    $("ps-finish").hidden = consent;
    if (consent) {
      $("ps-agree").textContent = screen.agree;
      $("ps-decline").textContent = screen.decline;
    } else {
      $("ps-finish").textContent = screen.button;
    }
    (consent ? $("ps-agree") : $("ps-finish")).focus();
  }

  const send = (message) => window.robinLive.send(message);
  $("ps-agree").addEventListener("click", () => send({ type: "consent", value: "agree" }));
  $("ps-decline").addEventListener("click", () => send({ type: "consent", value: "decline" }));
  $("ps-finish").addEventListener("click", () => send({ type: "finish" }));
  window.robinScreens = { show };
})();

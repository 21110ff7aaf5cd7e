// The questionnaire form shown between protocol blocks: built from the status the server
// pushes (phase "questionnaire"), answered with radio buttons, sent as one "answers" message.
"use strict";

(() => {
  const $ = (id) => document.getElementById(id);
  let shown = null; // "name#number" of the questionnaire on the form

  function build(status) {
    const q = status.questionnaire;
    $("q-title").textContent = q.title;
    $("q-progress").textContent = status.questionnaires > 1
      ? `questionnaire ${status.questionnaire_number} of ${status.questionnaires}` : "";
    $("q-instructions").textContent = q.instructions;
    const rows = q.items.map((item) => {
      const row = document.createElement("fieldset");
      row.className = "q-item";
      row.dataset.item = item.id;
      const legend = document.createElement("legend");
      legend.textContent = item.text;
      const scale = document.createElement("div");
      scale.className = "q-scale";
      const low = document.createElement("span");
      low.className = "q-anchor";
      low.textContent = item.low;
      scale.append(low);
      for (let value = item.min; value <= item.max; value += item.step) {
        const label = document.createElement("label");
        label.title = String(value);
        const input = document.createElement("input");
        input.type = "radio";
        input.name = `${q.name}-${item.id}`;
        input.value = String(value);
        input.addEventListener("change", () => row.classList.remove("missing"));
        label.append(input);
        if (item.max - item.min <= 10) label.append(document.createTextNode(String(value)));
        scale.append(label);
      }
      const high = document.createElement("span");
      high.className = "q-anchor";
      high.textContent = item.high;
      scale.append(high);
      row.append(legend, scale);
      return row;
    });
    $("q-items").replaceChildren(...rows);
    $("q-error").textContent = "";
    $("questionnaire").scrollTop = 0;
  }

  function submit(event) {
    event.preventDefault();
    const status = window.robinLive.status;
    if (!status || status.phase !== "questionnaire") return;
    const q = status.questionnaire;
    const answers = {};
    let missing = 0;
    for (const item of q.items) {
      const checked = document.querySelector(`input[name="${q.name}-${item.id}"]:checked`);
      const row = document.querySelector(`.q-item[data-item="${item.id}"]`);
      if (checked) {
        answers[item.id] = Number(checked.value);
      } else {
        missing += 1;
        row.classList.add("missing");
      }
    }
    if (missing) {
      $("q-error").textContent = `Please answer every question (${missing} still open).`;
      return;
    }
    window.robinLive.send({ type: "answers", questionnaire: q.name, answers });
  }

  function show(status) {
    const box = $("questionnaire");
    if (status.phase !== "questionnaire" || !status.questionnaire) {
      box.hidden = true;
      shown = null;
      return;
    }
    box.hidden = false;
    const key = `${status.questionnaire.name}#${status.questionnaire_number}`;
    if (key !== shown) {
      shown = key;
      build(status);
    }
    $("q-send").disabled = window.robinLive.role !== "control";
  }

  $("q-form").addEventListener("submit", submit);
  window.robinQuestionnaire = { show };
})();

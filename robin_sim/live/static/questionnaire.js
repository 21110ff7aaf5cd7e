// The questionnaire form shown between protocol blocks (and a study's demographics): built
// from the status the server pushes (phase "questionnaire"), one control per item kind (radio
// buttons for a scale or a choice, a slider for a visual analogue scale, a number field, a text
// box), sent as one "answers" message. Every control is reachable with Tab and set with keys.
"use strict";

(() => {
  const $ = (id) => document.getElementById(id);
  let shown = null; // "name#number" of the questionnaire on the form

  function radios(q, item, values, labels) {
    const scale = document.createElement("div");
    scale.className = item.kind === "choice" ? "q-scale q-choices" : "q-scale";
    if (item.kind === "scale") scale.append(anchor(item.low));
    values.forEach((value, k) => {
      const label = document.createElement("label");
      label.title = String(labels[k]);
      const input = document.createElement("input");
      input.type = "radio";
      input.name = `${q.name}-${item.id}`;
      input.value = String(value);
      label.append(input);
      if (item.kind === "choice" || item.max - item.min <= 10) {
        label.append(document.createTextNode(String(labels[k])));
      }
      scale.append(label);
    });
    if (item.kind === "scale") scale.append(anchor(item.high));
    return scale;
  }

  function anchor(text) {
    const span = document.createElement("span");
    span.className = "q-anchor";
    span.textContent = text;
    return span;
  }

  function control(q, item) {
    const name = `${q.name}-${item.id}`;
    if (item.kind === "scale") {
      const values = [];
      for (let v = item.min; v <= item.max; v += item.step) values.push(v);
      return radios(q, item, values, values);
    }
    if (item.kind === "choice") return radios(q, item, item.choices, item.labels);
    if (item.kind === "vas") {
      const box = document.createElement("div");
      box.className = "q-scale q-vas";
      const slider = document.createElement("input");
      slider.type = "range";
      slider.name = name;
      slider.min = String(item.min);
      slider.max = String(item.max);
      slider.step = "1";
      slider.value = String(Math.round((item.min + item.max) / 2));
      slider.dataset.touched = "";
      const value = document.createElement("output");
      value.textContent = "not set";
      slider.addEventListener("input", () => {
        slider.dataset.touched = "yes";
        value.textContent = slider.value;
      });
      box.append(anchor(item.low), slider, anchor(item.high), value);
      return box;
    }
    const field = document.createElement(item.kind === "text" ? "textarea" : "input");
    field.name = name;
    if (item.kind === "number") {
      field.type = "number";
      field.min = String(item.min);
      field.max = String(item.max);
      field.step = "1";
    } else {
      field.maxLength = item.max_length;
      field.rows = 2;
    }
    field.className = "q-field";
    return field;
  }

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
      row.dataset.kind = item.kind;
      const legend = document.createElement("legend");
      legend.textContent = item.text + (item.optional ? " (optional)" : "");
      const input = control(q, item);
      input.addEventListener("input", () => row.classList.remove("missing"));
      input.addEventListener("change", () => row.classList.remove("missing"));
      row.append(legend, input);
      return row;
    });
    $("q-items").replaceChildren(...rows);
    $("q-error").textContent = "";
    $("questionnaire").scrollTop = 0;
    const first = $("q-items").querySelector("input, textarea");
    if (first) first.focus();
  }

  // An item's answer as the server takes it; undefined while it is open.
  function answerOf(q, item) {
    const name = `${q.name}-${item.id}`;
    if (item.kind === "scale" || item.kind === "choice") {
      const checked = document.querySelector(`input[name="${name}"]:checked`);
      if (!checked) return undefined;
      return item.kind === "scale" ? Number(checked.value) : checked.value;
    }
    const field = document.querySelector(`[name="${name}"]`);
    if (item.kind === "vas") return field.dataset.touched ? Number(field.value) : undefined;
    const text = field.value.trim();
    if (!text) return undefined;
    return item.kind === "number" ? Number(text) : text;
  }

  function submit(event) {
    event.preventDefault();
    const status = window.robinLive.status;
    if (!status || status.phase !== "questionnaire") return;
    const q = status.questionnaire;
    const answers = {};
    let missing = 0;
    for (const item of q.items) {
      const value = answerOf(q, item);
      const row = document.querySelector(`.q-item[data-item="${item.id}"]`);
      if (value !== undefined) {
        answers[item.id] = value;
      } else if (!item.optional) {
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
    const key = `${status.questionnaire.name}#${status.questionnaire_number}#${status.block_number}`;
    if (key !== shown) {
      shown = key;
      build(status);
    }
    $("q-send").disabled = window.robinLive.role !== "control";
  }

  $("q-form").addEventListener("submit", submit);
  window.robinQuestionnaire = { show };
})();

"""The questionnaires after one block: shown one at a time, each answer saved as it comes.

:class:`Questioning` is the conductor's ``questionnaire`` phase for one block. Its status tells
the page which questionnaire to show (its items and scales); the page sends::

    {"type": "answers", "questionnaire": "nasa-tlx", "answers": {"mental": 55, ...}}

which is checked (every item, on its scale) and appended to the block's
``questionnaires.jsonl``: participant, session, condition, block, protocol, the questionnaire,
its answers and scores, and the wall time. :class:`LiveInputError` says what was wrong.
"""

from __future__ import annotations

import json
import time
from collections.abc import Mapping, Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Protocol

from pil.errors import quote
from pil.experiments.answers_file import RANGES_KEY
from pil.file_names import QUESTIONNAIRES_NAME
from robin_sim.live.config import LiveConfig
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.items import Answer, Questionnaire, QuestionnaireError

MAX_ANSWER_BYTES = 16 * 1024  # a questionnaire's answers are a few hundred bytes
ANSWER_FIELDS = ("type", "questionnaire", "answers")  # the fields of an answer message


class Inputs(Protocol):
    """Where a message of the page's is logged (:class:`robin_sim.live.session.LiveSession`)."""

    def record_input(self, raw: object, error: str) -> None: ...


class Questioning:
    """The block's questionnaires in order; :meth:`receive` takes the page's answers."""

    def __init__(
        self,
        questionnaires: Sequence[Questionnaire],
        folder: Path,
        config: LiveConfig,
        *,
        inputs: Inputs | None = None,
        file_name: str = QUESTIONNAIRES_NAME,
        context: Mapping[str, Any] | None = None,
    ) -> None:
        """``inputs``: where each message is logged, accepted or refused with why (the block's
        session: its ``inputs.jsonl``); ``file_name``: where in ``folder`` the answers go;
        ``context``: the fields each entry starts with (default: the block's participant,
        session, condition, block and protocol)."""
        self.questionnaires, self.folder, self.config = tuple(questionnaires), folder, config
        self.file_name, self.inputs = file_name, inputs
        self.context = dict(context) if context is not None else None
        self.index = 0
        self.shown_at = time.monotonic()

    @property
    def current(self) -> Questionnaire:
        return self.questionnaires[self.index]

    @classmethod
    def form(cls, form: Questionnaire, config: LiveConfig, file_name: str) -> Questioning:
        """A study's form before the blocks (demographics), saved as ``file_name`` in the
        participant's folder."""
        folder = Path(config.out_root) / config.participant
        context = {"participant": config.participant, "protocol": config.protocol}
        return cls([form], folder, config, file_name=file_name, context=context)

    def answered(self) -> list[str]:
        """The names of the questionnaires answered so far."""
        return [q.name for q in self.questionnaires[: self.index]]

    def status(self) -> dict[str, Any]:
        """The page's status fields while a questionnaire is shown."""
        return {
            "phase": "questionnaire",
            "turn": "participant",
            "robot_doing": "",
            "message": "please answer the questionnaire",
            "questionnaire": self.current.as_dict(),
            "questionnaire_number": self.index + 1,
            "questionnaires": len(self.questionnaires),
        }

    def receive(self, raw: str | bytes) -> bool:
        """Check, save and log one page message; True once the block's last one is answered."""
        try:
            done = self._receive(raw)
        except LiveInputError as error:
            if self.inputs is not None:
                self.inputs.record_input(raw, str(error))
            raise
        if self.inputs is not None:
            self.inputs.record_input(raw, "")
        return done

    def _receive(self, raw: str | bytes) -> bool:
        message = _decode(raw)
        name = message.get("questionnaire")
        if name != self.current.name:
            raise LiveInputError(
                f"answers: the questionnaire shown is {self.current.name!r}, got {quote(name)}"
            )
        try:
            answers = self.current.check_answers(message.get("answers"))
        except QuestionnaireError as error:
            raise LiveInputError(str(error)) from None
        self._save(answers)
        self.index += 1
        self.shown_at = time.monotonic()
        return self.index >= len(self.questionnaires)

    def _save(self, answers: dict[str, Answer]) -> None:
        config, questionnaire = self.config, self.current
        context = self.context
        if context is None:
            context = {
                "participant": config.participant,
                "session": self.folder.name,
                "condition": config.system,
                "block": config.block,
                "protocol": config.protocol,
            }
        entry = {
            **context,
            "questionnaire": questionnaire.name,
            "kind": questionnaire.kind,
            "answers": answers,
            "scores": questionnaire.scores(answers),
            RANGES_KEY: questionnaire.score_ranges(),
            "seconds_to_answer": round(time.monotonic() - self.shown_at, 1),
            "utc": datetime.now(UTC).isoformat(timespec="seconds"),
        }
        checks = questionnaire.attention(answers)
        if checks:
            entry["attention"] = checks
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            with (self.folder / self.file_name).open("a", encoding="utf-8") as file:
                file.write(json.dumps(entry) + "\n")
                file.flush()
        except OSError as error:  # the page is told; the answers stay on it to send again
            raise LiveInputError(
                f"the answers could not be saved ({error.strerror}); tell the experimenter"
            ) from None


def _decode(raw: str | bytes) -> dict[str, Any]:
    if len(raw) > MAX_ANSWER_BYTES:
        raise LiveInputError(
            f"answers: message of {len(raw)} bytes is too long (at most {MAX_ANSWER_BYTES})"
        )
    try:
        message = json.loads(raw)
    except (ValueError, RecursionError):
        raise LiveInputError(
            'answers: not a JSON message; send {"type": "answers", '
            '"questionnaire": NAME, "answers": {ITEM: NUMBER, ...}}'
        ) from None
    if not isinstance(message, dict) or message.get("type") != "answers":
        kind = message.get("type") if isinstance(message, dict) else None
        raise LiveInputError(
            f"{kind or 'message'}: a questionnaire is shown; answer it first (send type 'answers')"
        )
    unknown = [str(key) for key in message if key not in ANSWER_FIELDS]
    if unknown:
        raise LiveInputError(
            f"answers: unknown field(s) {', '.join(map(quote, unknown))}; an answer takes "
            + ", ".join(repr(k) for k in ANSWER_FIELDS)
        )
    return message

"""The names of the files the commands write and read, one each (import them, never retype).

An episode's folder (``robin-pil episode``), a live session's, a study's and a sweep's: the
writers and every reader (``report``, ``replay``, the study export, the appearance study)
take the name from here.
"""

from __future__ import annotations

SUMMARY_NAME = "summary.json"  # a run's summary: episodes, live sessions (their folders)
EPISODE_LOG_NAME = "episode.jsonl"  # an episode's step log
VIDEO_NAME = "episode.mp4"  # an episode's video
RUNS_NAME = "runs.csv"  # a study's rows, one per run
RESULTS_NAME = "results.csv"  # a sweep's rows, one per run, sorted by run id
MEASURED_NAME = "measured.json"  # the eye cameras' measured errors (robin-pil train-gestures)
QUESTIONNAIRES_NAME = "questionnaires.jsonl"  # a live session's questionnaire answers

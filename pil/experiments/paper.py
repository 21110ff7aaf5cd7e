"""The paper's simulation setup and the figures it reports (section IV-B), in one place.

Everything else that needs "the paper's rates" or "the paper's training cost" imports it from
here: the study's and the sweep's defaults, their command lines, the report beside our figures.
Tables, legs per table and training tables are scenario facts (``scenarios/assembly.yaml``).
"""

from __future__ import annotations

from pil.task.params import REPS

PAPER_RATES: tuple[float, ...] = (0.4, 0.6, 0.8, 1.0)  # the detection rates d simulated
PAPER_REPS: int = REPS.default  # each set of 10 tables was assembled 20 times per rate
BASELINE = "pil"  # the paper's learner: the system every other one is compared against
# The pre-trained conditions' training (5 tables): rate -> (gestures, actions)
PAPER_TRAINING: dict[float, tuple[int, int]] = {
    0.4: (170, 222),
    0.6: (148, 203),
    0.8: (126, 181),
    1.0: (111, 144),
}


LOW_RATES: tuple[float, ...] = (0.4, 0.6)  # where the paper says PIL costs more than c1, c2


def rates_text(rates: tuple[float, ...] = PAPER_RATES) -> str:
    """Rates as a command line takes them: ``"0.4,0.6,0.8,1.0"``."""
    return ",".join(str(float(rate)) for rate in rates)

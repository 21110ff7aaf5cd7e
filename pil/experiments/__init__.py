"""Experiments over learner runs: the study, its systems, reports, figures, sweeps (no MuJoCo)."""

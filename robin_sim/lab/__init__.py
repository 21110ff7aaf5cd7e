"""A lab's study of many participants: the study file, the registry, the assignment, the log,
the exports and the archive (the live page runs each participant: :mod:`robin_sim.live`)."""

"""The ``robin-pil`` command line: the entry point (:mod:`robin_sim.cli.main`), one module each."""

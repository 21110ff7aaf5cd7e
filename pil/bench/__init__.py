"""The gesture-action benchmark (docs/bench.md): the suite file, tracks, noise, agents, analysis."""

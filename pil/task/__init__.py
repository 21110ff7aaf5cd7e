"""The symbolic task: scenarios, the person, the detector, the world protocol, the step loop."""

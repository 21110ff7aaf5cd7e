"""The simulated person's body in the scene: the mocap hand, its gestures and thumbs, the palm."""

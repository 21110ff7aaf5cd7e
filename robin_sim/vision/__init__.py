"""Robin reads the person's gestures from its eye cameras (see docs/vision.md).

gaze (aim the head), eyes (render the eye cameras under a condition), segment (find the hand),
features (describe its crop), classifier (the shipped gesture model), dataset and train (the
``train-gestures`` data set and training), detector (:class:`VisionDetector`).
"""

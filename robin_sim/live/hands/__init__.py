"""The participant's own hand on a webcam (``robin-pil live --webcam``).

The page runs the hand tracker (MediaPipe Hands, vendored under ``static/vendor``) and sends
the 21 landmarks of each reading; no frame leaves the browser. This package reads them on the
server: :mod:`.landmarks` checks and normalises them, :mod:`.shape` reads a gesture from the
hand's shape, :mod:`.appearance` learns a person's own gestures (one-shot calibration, then
every confirmed or corrected reading), :mod:`.reader` turns readings into the session's inputs
and counts them for the summary's ``vision`` block. Nothing here needs MuJoCo.
"""

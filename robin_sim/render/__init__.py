"""Off-screen rendering: GL backend, renderers, render pool, video, overlay, render checks.

Importing this package imports nothing else: ``gl_backend`` must choose ``MUJOCO_GL`` before
MuJoCo is first imported.
"""

"""Robin's MJCF model and scene: the names the code uses, the robot's specification, the scene.

The MJCF files and scenarios ship inside the installed package (``robin_sim/model/mjcf``, a link
to the repository's ``models/`` in a source checkout).
"""

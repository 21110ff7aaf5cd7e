"""Robin's MJCF model and scene: the names the code uses, the robot's specification, the scene,
the person's joints (posed from ``userdata``), the pose library of real hands
(``data/hand_poses.json``) and the idle hand baked at one of its poses.

The MJCF files and scenarios ship inside the installed package (``robin_sim/model/mjcf``, a link
to the repository's ``models/`` in a source checkout).
"""

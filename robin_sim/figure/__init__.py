"""The person's kinematic figure, below the robot and the person's behaviour: the capsule hand's
signs (``hand_poses``), the articulated hand's joint poses (``articulated``) from the model's
pose library of real hands (``robin_sim.model.pose_library``), 21 landmarks to joint angles
(``retarget``) and the body that follows the hand (``posture``: the torso's least-cost step,
turn and lean in ``torso``, the arm's angles in closed form in ``arm_angles``, the idle arm
clear of the table in ``idle_arm``). It imports the model layer only (names, the person's
joints, the pose library), so the world, the person, the eyes and the live mirror can all use
it."""

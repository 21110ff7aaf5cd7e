"""Control: the simulator clock and actuators, mink IK, trajectories, the hand-state sensor."""

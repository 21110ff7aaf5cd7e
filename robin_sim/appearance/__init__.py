"""The appearance study: Robin's eye cameras reading people who look different, with the
shipped gesture model and with one adapting to each person from the robot's feedback."""

"""Robin in MuJoCo: the model, mink controllers for the five actions, episodes and rendering.

Importing this package does not import MuJoCo; the submodules that need it do.
"""

"""How simulated time is cut: simulation steps of 0.01 s, four to a policy step of 0.04 s.

The policy step is the one every robot strategy and human policy acts on (``ROBOT_DT`` in
``plugins/protocols.py``); a scene may refine ``dt`` as long as ``dt x frame_skip`` stays it.
"""

SIM_DT = 0.01  # s, one simulation step of the body and the cloth
FRAME_SKIP = 4  # simulation steps per policy step
POLICY_DT = SIM_DT * FRAME_SKIP  # s, one action of the human and of the robot (25 per second)

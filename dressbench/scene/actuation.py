"""How an action of the human drives its joints (docs/human.md), named once for the scene, the
training configuration and the policy files.

* ``pd``: the action is the PD target, absolute, around rest (dressbench's default);
* ``delta``: the action moves the PD target, at most as far as the PD lets a joint go in one
  policy step, so a zero action holds the pose;
* ``torque``: the paper's mapping, action x 10 N m.
"""

ACTUATIONS = ("pd", "delta", "torque")


def check_actuation(actuation: str) -> None:
    """Refuse an actuation that is not one of ``ACTUATIONS``, in one line."""
    if actuation not in ACTUATIONS:
        raise ValueError(f"unknown actuation {actuation!r}: use one of {', '.join(ACTUATIONS)}")

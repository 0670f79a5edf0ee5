"""Humans that pass the preflight (one act) and then fail in their episodes, and a robot whose
results cannot be repeated."""

import os
import sys
import time

import numpy as np


class Human:
    """The zero action, generic; ``misbehave`` from its second act on (the preflight acts once)."""

    api_version = 1
    robot = None
    ablation = "complete"

    def __init__(self) -> None:
        self.acts = 0

    def reset(self, seed=None):
        pass

    def act(self, observation):
        self.acts += 1
        if self.acts > 1:
            self.misbehave()
        return np.zeros(11)

    def misbehave(self) -> None:
        pass


class Crashy(Human):
    def misbehave(self) -> None:
        raise RuntimeError("boom")


class Quitter(Human):
    def misbehave(self) -> None:
        sys.exit(3)


class Vanisher(Human):
    def misbehave(self) -> None:
        os._exit(7)


class Sleeper(Human):
    def misbehave(self) -> None:
        time.sleep(600)


class WrongSize(Human):
    def act(self, observation):
        self.acts += 1
        return np.zeros(11 if self.acts == 1 else 10)


class Gambler:
    """The built-in fixed robot, but its start pose jitters by NumPy's global random state."""

    api_version = 1

    def reset(self, rng):
        from dressbench.plugins.robots import FixedGown

        jitter = np.random.uniform(-0.01, 0.01, 3)  # noqa: NPY002 - the fault under test
        return FixedGown().reset(rng) + np.r_[jitter, np.zeros(4)]

    def act(self, observation):
        return np.zeros(3)

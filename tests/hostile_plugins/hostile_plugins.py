"""Humans that pass the preflight (one act) and then fail in their episodes."""

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

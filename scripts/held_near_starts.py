"""Near starts of the curriculum's first level, held still: how often does the hand end in the
sleeve when the arm keeps its pose (zero ``delta`` actions) and only the robot moves?

The rate a learner's near starts should at least reach
(docs/experiments/2026-12-02-first-level-action-noise.md).
Run: python scripts/held_near_starts.py side_linear --episodes 20 --seed 100
"""

from __future__ import annotations

import argparse

import numpy as np

from dressbench.factory import make_human_env
from dressbench.training.curriculum import CurriculumConfig, NearStarts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robot")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=100, help="of the first episode")
    args = parser.parse_args()
    # every episode a near start of the first level
    coach = CurriculumConfig(share=1.0, held_share=1.0)
    env = NearStarts(make_human_env(args.robot, actuation="delta"), coach)
    hold = np.zeros(env.action_space.shape)
    finals = []
    for episode in range(args.episodes):
        _, info = env.reset(seed=args.seed + episode)
        distance, done = info["near_start"], False
        while not done:
            _, _, terminated, truncated, info = env.step(hold)
            done = terminated or truncated
        finals.append(info["arm_progress"])
        print(f"start {distance:.3f} m before the opening: final arm progress "
              f"{finals[-1]:.3f} m, max deformation {info['max_deformation']:.2f}")  # fmt: skip
    inside = np.mean(np.array(finals) >= coach.hand_in)
    print(f"{args.robot}: the hand ends in for {inside:.0%} of {args.episodes} held near starts")


if __name__ == "__main__":
    main()

"""How far the exploration noise of ``delta`` actions moves the fingertip in one policy step, per
actuated joint, at the curriculum's first-level near starts.

A ``delta`` action of a moves a PD target by a x ``Human.delta_step``; with actions N(0, std)
each joint's target steps by std x delta_step, and the fingertip by that times the joint's
lever (the norm of its column of the fingertip Jacobian),
docs/experiments/2026-12-03-noise-levers-paper-preset.md.
Run: python scripts/noise_levers.py side_linear --std 0.5 --starts 5
"""

from __future__ import annotations

import argparse

import numpy as np

from dressbench.factory import make_human_env
from dressbench.training.curriculum import CurriculumConfig, NearStarts

SPINE = 3  # the first actuated DOFs are the spine's; the rest the right arm's


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robot")
    parser.add_argument("--std", type=float, default=0.5, help="of the actions' noise")
    parser.add_argument("--starts", type=int, default=5, help="near starts averaged over")
    args = parser.parse_args()
    # every episode a near start of the first level
    coach = CurriculumConfig(share=1.0, held_share=1.0)
    env = NearStarts(make_human_env(args.robot, actuation="delta"), coach)
    human = env.unwrapped.env.scene.human
    levers = []
    for seed in range(args.starts):
        env.reset(seed=seed)
        jacobian = human.fingertip_jacobian(human.q.copy())[:, human.actuated_index]
        levers.append(np.linalg.norm(jacobian, axis=0))
    lever = np.mean(levers, axis=0)
    step = args.std * human.delta_step * lever  # m the fingertip moves per step, per joint
    print(f"delta step {human.delta_step:.3f} rad; actions N(0, {args.std})")
    print("lever (m/rad) per actuated DOF:", np.round(lever, 3).tolist())
    print("fingertip std per step from each DOF (cm):", np.round(100 * step, 2).tolist())
    total = float(np.sqrt((step**2).sum()))
    spine = float((step[:SPINE] ** 2).sum() / total**2)
    print(f"all together: {100 * total:.1f} cm per step; the spine's share of its variance: "
          f"{spine:.0%}")  # fmt: skip


if __name__ == "__main__":
    main()

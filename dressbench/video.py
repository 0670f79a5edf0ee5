"""Videos: frames written as .gif or .mp4, and one seeded rollout recorded as a video."""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .plugins.protocols import ROBOT_DT
from .render import rollout_caption, video_renderer

VIDEO_SUFFIXES = (".gif", ".mp4")


def save_video(frames: list[np.ndarray], path: str | Path, fps: int = round(1 / ROBOT_DT)) -> None:
    """Write frames as ``.gif`` (Pillow) or ``.mp4`` (imageio-ffmpeg), chosen by the suffix."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"cannot write video {path.name!r}: use a .gif or .mp4 suffix")
    if not frames:
        raise ValueError(f"no frames to write to {path.name!r}")
    _require_writer(suffix)
    import imageio.v3 as iio

    if suffix == ".gif":
        iio.imwrite(path, np.stack(frames), plugin="pillow", duration=1000.0 / fps, loop=0)
        return
    iio.imwrite(path, np.stack(frames), plugin="FFMPEG", fps=fps, macro_block_size=2)


def _require_writer(suffix: str) -> None:
    """The optional packages that write ``suffix`` videos are installed, or a one-line error."""
    _require("imageio", "imageio", suffix)
    if suffix == ".mp4":
        _require("imageio_ffmpeg", "imageio-ffmpeg", suffix)


def _require(module: str, package: str, suffix: str) -> None:
    """Import an optional video dependency, or say in one line which package to install."""
    try:
        importlib.import_module(module)
    except ImportError:
        raise RuntimeError(f"writing {suffix} needs {package}: pip install {package}") from None


@dataclass(frozen=True)
class Video:
    """A rollout video written to ``path``, and what its last caption shows: the episode's
    arm progress (m) and max deformation after ``steps`` policy steps."""

    path: Path
    arm_progress: float
    max_deformation: float
    steps: int

    def summary(self) -> str:
        """The last caption's numbers in words, for a line of output."""
        return (
            f"arm progress {100.0 * self.arm_progress:.1f} cm, max deformation "
            f"{self.max_deformation:.2f} after {self.steps} steps"
        )


def render_rollout(
    robot: str,
    human: str,
    path: str | Path,
    seed: int = 0,
    every: int = 2,
    fps: int | None = None,
    **options,
) -> Video:
    """Run one seeded rollout of a human plugin with a robot strategy and save it as a video.

    The env is the one the human was made for (its ablation and actuation), as in its
    evaluation, so the video shows the episode the evaluation scored for ``seed``. Every
    ``every``-th policy step becomes a frame; by default the video plays in real time. The path
    is checked before anything is rendered: a ``.gif`` or ``.mp4`` in a folder that exists,
    with its writer installed.
    """
    from .checks import check_int, check_output_file
    from .factory import make_human_env
    from .plugins import load_human

    path = check_output_file(path, VIDEO_SUFFIXES, "video")
    _require_writer(path.suffix.lower())
    check_int(every, "every", 1)
    if fps is not None:
        check_int(fps, "fps", 1)
    policy = load_human(human)
    env = make_human_env(robot, human=policy, **options)
    observation, info = env.reset(seed=seed)
    policy.reset(seed)
    renderer = video_renderer()
    scene = env.env.scene
    frames = [renderer.render(scene, rollout_caption(robot, human, 0.0, info), 0.0)]
    step = 0
    for step in range(1, env.env.config.horizon + 1):
        observation, _, terminated, truncated, info = env.step(policy.act(observation))
        if step % every == 0 or terminated or truncated:
            caption = rollout_caption(robot, human, step * ROBOT_DT, info)
            frames.append(renderer.render(scene, caption, info.get("arm_progress", 0.0)))
        if terminated or truncated:
            break
    save_video(frames, path, fps=fps or round(1 / (ROBOT_DT * every)))
    return Video(Path(path), float(info["arm_progress"]), float(info["max_deformation"]), step)

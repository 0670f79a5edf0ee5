"""Headless rendering: frames have the right shape, show the body and the gown, follow the arm,
do not depend on what the renderer drew before, and save as GIF (and MP4 when available)."""

import sys

import numpy as np
import pytest
from matplotlib.colors import rgb_to_hsv

from dressbench.render import GOWN, SKIN, Renderer, render_frame
from dressbench.scene.garment import GownConfig
from dressbench.scene.world import Scene, SceneConfig
from dressbench.video import save_video

GRIPPER = np.array([0.45, -0.19, 0.52, 0.0, 0.0, 0.0, 1.0])  # in front of the right shoulder
W, H = 240, 180  # small frames keep the tests fast


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene(SceneConfig(gown=GownConfig(target_vertices=600)))


@pytest.fixture(scope="module")
def renderer() -> Renderer:
    return Renderer(W, H)


@pytest.fixture
def rest(scene: Scene) -> Scene:
    """The module's scene reset to the human at rest and the gown held in front of them."""
    scene.reset(GRIPPER)
    return scene


def outstretched(scene: Scene) -> np.ndarray:
    """Right arm straight ahead at shoulder height, everything else at rest."""
    q = scene.human.rest.copy()
    q[8:12] = [0.0, 0.0, np.pi / 2, 0.0]  # shoulder elevation, middle axis, swing; elbow
    return q


def pixels_of(frame: np.ndarray, rgb: np.ndarray) -> int:
    """How many pixels have the hue of ``rgb`` (shading and transparency keep the hue)."""
    hsv = rgb_to_hsv(frame / 255.0)
    hue = rgb_to_hsv(rgb)[0]
    near = np.abs((hsv[..., 0] - hue + 0.5) % 1.0 - 0.5) < 0.03
    return int((near & (hsv[..., 1] > 0.2)).sum())


def test_frame_is_rgb_image_of_the_scene(rest: Scene, renderer: Renderer) -> None:
    frame = renderer.render(rest)
    assert frame.shape == (H, W, 3) and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 100
    assert pixels_of(frame, GOWN) > 0.02 * W * H
    assert pixels_of(frame, SKIN) > 0.02 * W * H


def test_frame_follows_the_arm(rest: Scene, renderer: Renderer) -> None:
    before = renderer.render(rest)
    rest.reset(GRIPPER, outstretched(rest))
    after = renderer.render(rest)
    changed = np.any(before != after, axis=-1)
    assert changed.sum() > 0.01 * W * H


def test_frame_does_not_depend_on_earlier_frames(rest: Scene, renderer: Renderer) -> None:
    renderer.render(rest, caption="t = 1.00 s")
    again = renderer.render(rest)
    np.testing.assert_array_equal(again, render_frame(rest, W, H))
    assert np.any(renderer.render(rest, caption="t = 1.00 s") != again)


def test_gif_round_trip(rest: Scene, renderer: Renderer, tmp_path) -> None:
    iio = pytest.importorskip("imageio.v3")
    frames = [renderer.render(rest, caption=f"{k}") for k in range(3)]
    save_video(frames, tmp_path / "clip.gif", fps=10)
    back = iio.imread(tmp_path / "clip.gif", index=None)
    assert back.shape[0] == 3 and back.shape[1:3] == (H, W)


def test_mp4_round_trip(rest: Scene, renderer: Renderer, tmp_path) -> None:
    ffmpeg = pytest.importorskip("imageio_ffmpeg")
    frames = [renderer.render(rest, caption=f"{k}") for k in range(3)]
    save_video(frames, tmp_path / "clip.mp4", fps=10)
    reader = ffmpeg.read_frames(str(tmp_path / "clip.mp4"))
    meta = next(reader)
    reader.close()  # stops ffmpeg
    assert tuple(meta["size"]) == (W, H) and meta["fps"] == 10
    assert ffmpeg.count_frames_and_secs(str(tmp_path / "clip.mp4"))[0] == 3


@pytest.mark.parametrize(
    ("missing", "suffix", "package"),
    [("imageio_ffmpeg", ".mp4", "imageio-ffmpeg"), ("imageio", ".gif", "imageio")],
)
def test_missing_writer_says_what_to_install(missing, suffix, package, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, missing, None)  # importing it now raises ImportError
    frame = np.zeros((H, W, 3), np.uint8)
    with pytest.raises(RuntimeError, match=f"pip install {package}$"):
        save_video([frame], tmp_path / f"clip{suffix}")


def test_unknown_suffix_and_no_frames_are_refused(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"\.gif or \.mp4"):
        save_video([np.zeros((H, W, 3), np.uint8)], tmp_path / "clip.avi")
    with pytest.raises(ValueError, match="no frames"):
        save_video([], tmp_path / "clip.gif")


def test_video_frames_show_two_views_side_by_side_with_a_caption_that_fits(rest: Scene) -> None:
    from dressbench.render import VIDEO_SIZE, rollout_caption, video_renderer

    renderer = video_renderer()
    info = {"arm_progress": 0.123, "max_deformation": 1.5, "contact_force": 12.3}
    caption = rollout_caption("front_linear", "fixed-complete-trpo-s0", 12.34, info)
    frame = renderer.render(rest, caption, progress=0.123)
    width, height = VIDEO_SIZE
    assert width >= 960 and height >= 540 and frame.shape == (height, width, 3)
    assert "12.3 cm" in caption and "1.50" in caption and "12.3 N" in caption
    left, right = frame[:, : width // 2], frame[:, width // 2 :]
    for half in (left, right):  # each view shows the body and the gown
        assert pixels_of(half, SKIN) > 0.01 * half.shape[0] * half.shape[1]
        assert pixels_of(half, GOWN) > 0.005 * half.shape[0] * half.shape[1]
    assert np.abs(left.astype(int) - right.astype(int)).mean() > 5  # two different cameras
    assert len(renderer.panels) == 2 and renderer.panels[0].view != renderer.panels[1].view
    text = renderer.caption.get_window_extent(renderer.canvas.get_renderer())
    assert 0 <= text.x0 and text.x1 <= width and text.y1 <= height  # the caption is not cut
    assert renderer.bar_fill.get_width() == pytest.approx(0.123)  # the progress bar


def test_rollout_video_is_two_views_at_video_size(tmp_path) -> None:
    iio = pytest.importorskip("imageio.v3")
    from dressbench.render import VIDEO_SIZE
    from dressbench.video import render_rollout

    for suffix in (".gif", ".mp4"):
        video = render_rollout("fixed", "scripted", tmp_path / f"clip{suffix}", every=2,
                               horizon=4, gown_vertices=300)  # fmt: skip
        frames = iio.imread(video.path, index=None)
        assert frames.shape[1:3] == (VIDEO_SIZE[1], VIDEO_SIZE[0]) and len(frames) >= 2

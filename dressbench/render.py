"""Headless pictures of a dressing scene: capsule human, gown mesh and gripper, drawn by Agg.

Matplotlib's Agg canvas needs no display and no GPU, and a ``Figure`` made without pyplot holds
no global state. Everything solid is one ``Poly3DCollection`` so that the body and the gown
are depth-sorted together (painter's algorithm); the armhole loop and the gripper are lines and
a marker drawn on top, so they stay visible through the cloth and the arm in it.
See ``docs/render.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Rectangle
from mpl_toolkits.mplot3d import Axes3D
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from .metrics import STAGE_DEPTHS
from .scene.body import ARM_LENGTH
from .scene.geometry import quat_matrix
from .scene.world import Scene

SKIN = np.array([0.92, 0.70, 0.55])  # the human's capsules
GOWN = np.array([0.45, 0.68, 0.95])  # the gown's faces, semi-opaque
GOWN_ALPHA = 0.8
GRIPPER = (0.20, 0.20, 0.25)  # the gripper's marker
LOOP_COLOR = (0.05, 0.15, 0.55)  # the armhole loop, a closed line
AXIS_COLOR = (0.85, 0.10, 0.10)  # the gripper's approach axis
AMBIENT = 0.35  # share of a face's colour that needs no light
SIDES = 8  # facets around each capsule
CAP_ANGLES = np.radians([-90.0, -45.0, 0.0, 0.0, 45.0, 90.0])  # latitudes of the capsule rings
CAP_ENDS = np.array([0, 0, 0, 1, 1, 1])  # the endpoint each ring is centred on
AXIS_LENGTH = 0.2  # m, drawn length of the approach axis
RENDER_VERSION = 3  # bumped when videos look different: cached report videos are redrawn
# (3: a human runs under its own actuation, so a video shows the episode its cell scored)


@dataclass(frozen=True)
class View:
    """A fixed camera and the world box it frames (metres, the scene's frame)."""

    elev: float = 15.0  # degrees above the horizon
    azim: float = -60.0  # degrees about z from +x: the camera stands front-right of the human
    xlim: tuple[float, float] = (-0.4, 1.1)
    ylim: tuple[float, float] = (-0.9, 0.6)
    zlim: tuple[float, float] = (-0.6, 1.0)
    zoom: float = 1.5  # the box fills more of the frame than matplotlib's default margin
    title: str = ""  # drawn at the panel's top left when the frame has several views

    def light(self) -> np.ndarray:
        """Unit light direction: from over the camera's shoulder, so visible faces are lit."""
        e, a = np.radians(self.elev + 30.0), np.radians(self.azim + 20.0)
        return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


# Videos: two views side by side, a see-through gown, the arm's bones drawn on top.
FRONT_THREE_QUARTER = View(elev=18.0, azim=-45.0, zoom=1.7, title="front three-quarter")
SIDE = View(elev=6.0, azim=-90.0, zoom=1.7, title="side (from the right)")
VIDEO_VIEWS = (FRONT_THREE_QUARTER, SIDE)
VIDEO_SIZE = (960, 540)
VIDEO_GOWN_ALPHA = 0.45  # translucent: the arm shows through the sleeve
ARM_COLOR = (0.55, 0.25, 0.10)  # the right arm's bones (fingertip-wrist-elbow-shoulder)
BAR_COLOR = (0.15, 0.55, 0.25)  # the progress bar's fill
BAR_MARKS = tuple(zip(("hand in", "elbow", "dressed"), STAGE_DEPTHS.values(), strict=True))
CAPTION_SHARE = 0.16  # of the height, at the top: the caption (two lines), the views' titles
BAR_SHARE = 0.09  # of the height, at the bottom, for the progress bar with a HUD


class _Panel:
    """One view of the scene in a rectangle of the figure: its 3-D axes and artists."""

    def __init__(
        self, figure: Figure, rect: tuple[float, float, float, float], view: View, size: float,
        gown_alpha: float, arm: bool, titled: bool,
    ) -> None:  # fmt: skip
        self.view = view
        self.gown_alpha = gown_alpha
        self.axes = _make_axes(figure, view, rect)
        self.solids = Poly3DCollection(
            np.zeros((0, 4, 3)), edgecolors="none", linewidths=0.0, antialiased=False, zorder=1
        )
        self.axes.add_collection3d(self.solids)
        (self.loop,) = self.axes.plot([], [], [], color=LOOP_COLOR, lw=2.0 * size, zorder=2)
        (self.axis,) = self.axes.plot([], [], [], color=AXIS_COLOR, lw=2.5 * size, zorder=3)
        (self.gripper,) = self.axes.plot(
            [], [], [], "s", color=GRIPPER, mec="white", mew=size, ms=8 * size, zorder=4
        )
        self.arm = None
        if arm:
            (self.arm,) = self.axes.plot(
                [], [], [], "-o", color=ARM_COLOR, lw=1.6 * size, ms=3.5 * size, zorder=5
            )
        if titled and view.title:  # just above the panel, where the body never reaches
            left, bottom, _, height = rect
            figure.text(
                left + 0.015, bottom + height + 0.005, view.title, va="bottom",
                fontsize=8 * size, color=(0.35, 0.35, 0.35), zorder=6,
            )  # fmt: skip

    def draw(self, scene: Scene, body: np.ndarray, gown: np.ndarray, x: np.ndarray) -> None:
        light = self.view.light()
        colors = [
            shade(body, SKIN, 1.0, light, two_sided=False),
            shade(gown, GOWN, self.gown_alpha, light, two_sided=True),
        ]
        self.solids.set_verts(np.concatenate([body, gown]))
        self.solids.set_facecolor(np.concatenate(colors))
        loop = x[np.append(scene.gown.feature_loop, scene.gown.feature_loop[0])]
        self.loop.set_data_3d(*loop.T)
        pose = scene.gripper_pose
        self.axis.set_data_3d(*approach_axis(pose, AXIS_LENGTH).T)
        self.gripper.set_data_3d(*pose[:3, None])
        if self.arm is not None:
            self.arm.set_data_3d(*scene.arm_chain().T)


class Renderer:
    """One reusable Agg figure of a fixed size; ``render`` redraws it for each frame.

    ``Renderer(width, height, view)`` draws one view (``render_mode="rgb_array"``).
    ``Renderer(width, height, views=VIDEO_VIEWS, hud=True)`` (see ``video_renderer``) draws
    the views side by side with a caption area above them and a progress bar of the arm's
    depth in the sleeve below them; the arm's bones are drawn on top of the gown.
    """

    def __init__(
        self,
        width: int = 480,
        height: int = 360,
        view: View = View(),
        *,
        views: tuple[View, ...] | None = None,
        gown_alpha: float = GOWN_ALPHA,
        hud: bool = False,
    ) -> None:
        self.views = tuple(views) if views else (view,)
        self.view = self.views[0]
        self.width, self.height = width, height
        self.figure = Figure(figsize=(width / 100, height / 100), dpi=100)
        self.canvas = FigureCanvasAgg(self.figure)
        size = height / 360  # lines, marker and text keep their share of the frame at any size
        bottom, top = (BAR_SHARE, 1.0 - CAPTION_SHARE) if hud else (0.0, 1.0)
        share = 1.0 / len(self.views)
        several = len(self.views) > 1
        self.panels = [
            _Panel(
                self.figure,
                (i * share, bottom, share, top - bottom),
                v,
                size,
                gown_alpha,
                arm=hud,
                titled=several,
            )  # fmt: skip
            for i, v in enumerate(self.views)
        ]
        self.axes = self.panels[0].axes
        for i in range(1, len(self.views)):  # a thin rule between the views
            self.figure.add_artist(
                Line2D([i * share] * 2, [bottom + 0.02, top - 0.02], color=(0.8, 0.8, 0.8),
                       lw=size, transform=self.figure.transFigure)
            )  # fmt: skip
        self.caption = self.figure.text(
            0.02 if not hud else 0.015, 0.97 if not hud else 0.985, "", va="top",
            family="monospace", fontsize=(10 if not hud else 8.5) * size, zorder=5,
            linespacing=1.3,
        )  # fmt: skip
        self.bar = self.bar_fill = self.bar_value = None
        if hud:
            self._make_bar(size)

    def _make_bar(self, size: float) -> None:
        """A thin horizontal gauge of arm progress, 0 to the arm's length, the stages marked."""
        bar = self.figure.add_axes((0.2, BAR_SHARE * 0.6, 0.6, BAR_SHARE * 0.28))
        bar.set_xlim(0.0, ARM_LENGTH)
        bar.set_ylim(0.0, 1.0)
        bar.set_yticks([])
        bar.set_xticks([depth for _, depth in BAR_MARKS])
        bar.set_xticklabels(
            [f"{name} {depth * 100:.0f}" for name, depth in BAR_MARKS], fontsize=7 * size
        )
        bar.tick_params(length=2 * size, pad=1.5 * size)
        for depth in (d for _, d in BAR_MARKS):
            bar.axvline(depth, color=(0.4, 0.4, 0.4), lw=0.8 * size)
        for spine in bar.spines.values():
            spine.set_linewidth(0.6 * size)
        bar.set_facecolor((0.93, 0.93, 0.93))
        self.bar_fill = Rectangle((0.0, 0.0), 0.0, 1.0, color=BAR_COLOR)
        bar.add_patch(self.bar_fill)
        self.figure.text(0.19, BAR_SHARE * 0.74, "arm in sleeve (cm)", ha="right", va="center",
                         fontsize=7 * size)  # fmt: skip
        self.bar_value = self.figure.text(0.81, BAR_SHARE * 0.74, "", ha="left", va="center",
                                          fontsize=7 * size, family="monospace")  # fmt: skip
        self.bar = bar

    def render(
        self, scene: Scene, caption: str | None = None, progress: float | None = None
    ) -> np.ndarray:
        """The scene as an (H, W, 3) uint8 RGB image; ``progress`` (m) fills the bar."""
        x = scene.cloth_positions()
        body = body_faces(scene.human.capsules(scene.transforms), scene.human.capsule_radius)
        gown = pad_to_quads(x[scene.gown.triangles])
        for panel in self.panels:
            panel.draw(scene, body, gown, x)
        if self.bar_fill is not None:
            depth = min(max(progress or 0.0, 0.0), ARM_LENGTH)
            self.bar_fill.set_width(depth)
            self.bar_value.set_text(f"{100.0 * (progress or 0.0):.1f} cm")
        self.caption.set_text(caption or "")
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[:, :, :3].copy()


def video_renderer(width: int = VIDEO_SIZE[0], height: int = VIDEO_SIZE[1]) -> Renderer:
    """The renderer of rollout videos: front three-quarter and side views side by side, a
    translucent gown, the arm's bones, a two-line caption and the progress bar."""
    return Renderer(width, height, views=VIDEO_VIEWS, gown_alpha=VIDEO_GOWN_ALPHA, hud=True)


def rollout_caption(robot: str, human: str, seconds: float, info: dict | None = None) -> str:
    """Two lines: who, then time, arm progress (cm), max deformation and contact force."""
    info = info or {}
    progress = 100.0 * float(info.get("arm_progress", 0.0))
    deformation = info.get("max_deformation")
    force = info.get("contact_force")
    return (
        f"{robot} / {human}\n"
        f"t {seconds:5.2f} s   arm progress {progress:5.1f} cm   "
        f"max deformation {'-' if deformation is None else f'{deformation:.2f}'}   "
        f"contact force {'-' if force is None else f'{force:.1f} N'}"
    )


def render_frame(
    scene: Scene,
    width: int = 480,
    height: int = 360,
    view: View = View(),
    caption: str | None = None,
) -> np.ndarray:
    """One (H, W, 3) uint8 frame from a fresh figure; hold a ``Renderer`` to draw many faster."""
    return Renderer(width, height, view).render(scene, caption)


def _make_axes(
    figure: Figure, view: View, rect: tuple[float, float, float, float] = (0.0, 0.0, 1.0, 1.0)
) -> Axes3D:
    """3-D axes in ``rect`` (the full frame by default) with equal aspect, fixed limits and
    camera, and nothing but data."""
    ax = figure.add_axes(rect, projection="3d", computed_zorder=False)
    ax.set_xlim(view.xlim)
    ax.set_ylim(view.ylim)
    ax.set_zlim(view.zlim)
    spans = [hi - lo for lo, hi in (view.xlim, view.ylim, view.zlim)]
    ax.set_box_aspect(spans, zoom=view.zoom)
    ax.view_init(elev=view.elev, azim=view.azim)
    ax.set_axis_off()
    return ax


def capsule_rings(capsules: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """(C, 6, SIDES, 3) rings of points around each capsule: two hemispheres and a cylinder."""
    a, b = capsules[:, 0], capsules[:, 1]
    w = b - a
    length = np.linalg.norm(w, axis=1, keepdims=True)
    w = np.where(length > 1e-9, w / np.maximum(length, 1e-9), [0.0, 0.0, 1.0])
    helper = np.where(np.abs(w[:, 2:3]) < 0.9, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    u = np.cross(w, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(w, u)
    theta = np.linspace(0.0, 2.0 * np.pi, SIDES, endpoint=False)
    around = np.cos(theta)[:, None, None] * u + np.sin(theta)[:, None, None] * v  # (S, C, 3)
    centre = capsules[:, CAP_ENDS]  # (C, 6, 3)
    r = radius[:, None, None, None]
    lat = CAP_ANGLES[None, :, None, None]
    radial = np.cos(lat) * around.transpose(1, 0, 2)[:, None]  # (C, 6, S, 3)
    return centre[:, :, None] + r * (radial + np.sin(lat) * w[:, None, None])


def body_faces(capsules: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """(C * 5 * SIDES, 4, 3) outward quads tiling every capsule between consecutive rings."""
    rings = capsule_rings(capsules, radius)
    nxt = np.roll(np.arange(SIDES), -1)
    lo, hi = rings[:, :-1], rings[:, 1:]
    quads = np.stack([lo, lo[:, :, nxt], hi[:, :, nxt], hi], axis=3)  # (C, 5, S, 4, 3)
    return quads.reshape(-1, 4, 3)


def pad_to_quads(triangles: np.ndarray) -> np.ndarray:
    """(F, 4, 3) from (F, 3, 3) by repeating the last corner, so all faces share one array."""
    return np.concatenate([triangles, triangles[:, 2:]], axis=1)


def approach_axis(pose: np.ndarray, length: float) -> np.ndarray:
    """(2, 3) segment from the gripper along its local +x, the way the arm enters the sleeve."""
    return pose[:3] + np.outer([0.0, length], quat_matrix(pose[3:])[:, 0])


def shade(
    faces: np.ndarray, rgb: np.ndarray, alpha: float, light: np.ndarray, two_sided: bool
) -> np.ndarray:
    """(F, 4) RGBA per face: Lambert shading of its normal, so the surface's shape reads."""
    normal = np.cross(faces[:, 2] - faces[:, 0], faces[:, 3] - faces[:, 1])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-12)
    cosine = normal @ light
    lit = np.abs(cosine) if two_sided else np.maximum(cosine, 0.0)
    intensity = AMBIENT + (1.0 - AMBIENT) * lit
    out = np.empty((len(faces), 4))
    out[:, :3] = intensity[:, None] * rgb
    out[:, 3] = alpha
    return out

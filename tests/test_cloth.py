"""Cloth solver details: constraint colouring and its parallel launch path."""

from dataclasses import replace

import numpy as np

from dressbench.bench import BENCH_GRIPPER, reach_action
from dressbench.scene.cloth import ClothConfig, color_constraints
from dressbench.scene.garment import GownConfig, make_gown
from dressbench.scene.world import Scene, SceneConfig


def test_no_two_constraints_of_one_colour_share_a_vertex():
    gown = make_gown(GownConfig(target_vertices=800))
    for pairs in (gown.edges, gown.bend_pairs):
        colors = color_constraints(pairs)
        for c in np.unique(colors):
            vertices = pairs[colors == c].ravel()
            assert len(vertices) == len(np.unique(vertices))
        assert colors.max() < 16  # a handful of colours, not one per constraint


def test_launching_colour_by_colour_gives_the_same_cloth():
    """The CUDA launch path (one launch per colour) is the same sweep as the CPU's."""

    def run(per_color: bool) -> np.ndarray:
        cloth = replace(ClothConfig(), launch_per_color=per_color)
        scene = Scene(SceneConfig(gown=GownConfig(target_vertices=600), cloth=cloth))
        scene.reset(BENCH_GRIPPER)
        for k in range(10):
            scene.step(reach_action(k, period=20), BENCH_GRIPPER)
        return scene.cloth_positions()

    np.testing.assert_array_equal(run(False), run(True))

"""The observation's layout and the log scale a learned policy may read the forces on."""

from __future__ import annotations

import numpy as np
import pytest

from dressbench.observation import N_SENSORS, observation_layout, observation_size, scale_haptics

FORCES = observation_layout().forces


def _with_forces(forces: np.ndarray) -> np.ndarray:
    obs = np.arange(observation_size(), dtype=np.float32)
    obs[FORCES] = forces.ravel()
    return obs


def test_the_log_scale_keeps_each_force_direction_and_compresses_its_magnitude() -> None:
    forces = np.zeros((N_SENSORS, 3))
    forces[0] = [0.0, 0.0, 1.0]  # 1 N: log(2)
    forces[1] = [300.0, 400.0, 0.0]  # 500 N at a rigid rim: log(501)
    scaled = scale_haptics(_with_forces(forces), "complete", "log")[FORCES].reshape(-1, 3)
    np.testing.assert_allclose(scaled[0], [0.0, 0.0, np.log(2.0)], rtol=1e-6)
    np.testing.assert_allclose(scaled[1], np.log(501.0) * np.array([0.6, 0.8, 0.0]), rtol=1e-6)
    assert not scaled[2:].any()  # no contact stays exactly zero


def test_only_the_forces_change_and_newtons_changes_nothing() -> None:
    obs = _with_forces(np.full((N_SENSORS, 3), 7.0))
    scaled = scale_haptics(obs, "complete", "log")
    outside = np.ones(obs.shape, bool)
    outside[FORCES] = False
    np.testing.assert_array_equal(scaled[outside], obs[outside])
    assert scale_haptics(obs, "complete", "newtons") is obs
    short = np.zeros(observation_size("no_haptics"), np.float32)
    assert scale_haptics(short, "no_haptics", "log") is short


def test_a_batch_scales_like_each_of_its_rows() -> None:
    rng = np.random.default_rng(0)
    batch = rng.normal(0.0, 50.0, (4, observation_size())).astype(np.float32)
    rows = [scale_haptics(row, "complete", "log") for row in batch]
    np.testing.assert_allclose(scale_haptics(batch, "complete", "log"), rows, rtol=1e-6)


def test_the_layout_tiles_each_ablations_observation_in_the_documented_order() -> None:
    for ablation, size in (("complete", 163), ("no_haptics", 75), ("no_task", 160)):
        layout = observation_layout(ablation)
        blocks = [b for b in vars(layout).values() if isinstance(b, slice)]
        assert [b.start for b in blocks] == [0] + [b.stop for b in blocks[:-1]]
        assert blocks[-1].stop == layout.size == size
    assert observation_layout("no_haptics").forces is None
    assert observation_layout("no_task").task is None


def test_an_unknown_scale_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown haptic scale 'kg'"):
        scale_haptics(np.zeros(observation_size(), np.float32), "complete", "kg")

"""Capability profiles: each built-in does what it claims in the real physics, the typical one
changes nothing, a third party's is found, checked and used, a broken one is one line naming it,
and a human runs only under the profile it was trained for.

The built-ins are found through dressbench's own entry points (``pip install -e .`` registers
them); the third-party profiles are fake distributions on ``sys.path`` (``tests/fakes.py``).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from fakes import install

import dressbench
from dressbench.config import EnvConfig
from dressbench.env import HUMAN, ROBOT, DressingEnv
from dressbench.evaluation.cells import make_cell
from dressbench.evaluation.listing import plugin_rows
from dressbench.evaluation.rollouts import Runner
from dressbench.evaluation.runs import profiles_cells
from dressbench.factory import make_human_env
from dressbench.plugins import (
    PROFILE_GROUP,
    TYPICAL_PROFILE,
    BrokenPluginError,
    UnknownPluginError,
    load_human,
    load_profile,
    load_robot,
    profile_plugins,
    refresh,
)
from dressbench.plugins.profiles import (
    RIGHT_ARM,
    RIGHT_SHOULDER,
    LimitedShoulder,
    Tremor,
    Typical,
    WeakArm,
    dof_indices,
)
from dressbench.preflight import profile_problem
from dressbench.scene.body import BODY, DOF_NAMES, N_DOFS, body_limits, with_limits
from dressbench.scene.human import Human, HumanConfig
from dressbench.testing import check_profile_plugin
from dressbench.training.config import TrainConfig

SMALL = {"gown_vertices": 300}  # the checks' coarse gown: these are tests of the body
BUILT_INS = ("typical", "limited_shoulder", "weak_arm", "tremor")
PROFILES = f"[{PROFILE_GROUP}]"
# rad: DART enforces a joint limit as a soft constraint, which a joint driven into it presses up
# to ~0.07 rad past (measured under maximal torques)
LIMIT_TOLERANCE = 0.1


def maximal(env, steps: int, actions: list[np.ndarray]) -> np.ndarray:
    """q after each of ``steps`` policy steps of each action in turn, the robot still."""
    env.reset(seed=0)
    qs = []
    for action in actions:
        for _ in range(steps):
            env.step({HUMAN: action, ROBOT: np.zeros(3)})
            qs.append(env.scene.human.q)
    return np.array(qs)


# --- the built-ins are plugins like any other ---------------------------------------------------


def test_the_built_in_profiles_are_listed_from_dressbench_and_pass_their_check():
    found = profile_plugins()
    for name in BUILT_INS:
        assert name in found, f"{name!r} is not registered: reinstall dressbench (pip install -e .)"
        assert (found[name].package, found[name].status) == ("dressbench", "ok")
        assert profile_problem(name) is None
    listed = {(row[0], row[1]) for row in plugin_rows()}
    assert {("profile", name) for name in BUILT_INS} <= listed


@pytest.mark.parametrize("name", BUILT_INS)
def test_the_built_in_profiles_pass_the_authors_check(name):
    check_profile_plugin(name)


def test_the_authors_check_names_an_unseeded_profile():
    class Unseeded(Tremor):
        def involuntary(self, rng, frames, dt):
            return super().involuntary(np.random.default_rng(), frames, dt)

    with pytest.raises(AssertionError, match="Unseeded: involuntary must draw only from the rng"):
        check_profile_plugin(Unseeded())


def test_every_env_is_typical_unless_told():
    assert EnvConfig().profile == TrainConfig().profile == TYPICAL_PROFILE == "typical"
    assert dressbench.make_env("fixed", horizon=2, **SMALL).config.profile == "typical"


# --- typical: the body as it is -----------------------------------------------------------------


def test_typical_leaves_the_body_plan_as_it_is():
    typical = Typical()
    assert with_limits(BODY, typical.body(body_limits())) == BODY
    assert typical.involuntary(np.random.default_rng(0), 40, 0.01) is None


def test_typical_gives_bitwise_the_episode_of_no_profile():
    def episode(env) -> list[tuple]:
        env.reset(seed=5)
        rng = np.random.default_rng(1)
        steps = []
        for _ in range(12):
            action = rng.uniform(-1.0, 1.0, 11)
            observations, rewards, *_ = env.step({HUMAN: action, ROBOT: np.zeros(3)})
            steps.append((observations[HUMAN], rewards[HUMAN], env.scene.human.q))
        return steps

    config = EnvConfig(horizon=12, **SMALL)
    plain = episode(DressingEnv(load_robot("fixed"), config))  # no profile at all
    typical = episode(dressbench.make_env("fixed", profile="typical", horizon=12, **SMALL))
    for (obs, reward, q), (obs_t, reward_t, q_t) in zip(plain, typical, strict=True):
        assert np.array_equal(obs, obs_t) and reward == reward_t and np.array_equal(q, q_t)


# --- limited_shoulder: a range of motion --------------------------------------------------------


@pytest.mark.parametrize("actuation", ["pd", "torque"])
def test_a_limited_shoulder_never_passes_its_capped_limits_under_maximal_actions(actuation):
    env = dressbench.make_env("fixed", profile="limited_shoulder", actuation=actuation,
                              horizon=120, **SMALL)  # fmt: skip
    typical, capped = body_limits(), env.scene.human
    shoulder = dof_indices(RIGHT_SHOULDER)
    assert np.array_equal(capped.lower, LimitedShoulder().body(typical).lower)
    assert (capped.lower[shoulder] > typical.lower[shoulder]).all()
    assert (capped.upper[shoulder] < typical.upper[shoulder]).all()
    actions = [np.ones(11), -np.ones(11), np.ones(11)]
    qs = maximal(env, 40, actions)[:, shoulder]
    assert (qs >= capped.lower[shoulder] - LIMIT_TOLERANCE).all()
    assert (qs <= capped.upper[shoulder] + LIMIT_TOLERANCE).all()
    if actuation == "pd":  # the caps bind: the typical shoulder goes well past them
        free = dressbench.make_env("fixed", horizon=120, **SMALL)
        typical_qs = maximal(free, 40, actions)[:, shoulder]
        assert (typical_qs < capped.lower[shoulder] - LIMIT_TOLERANCE).any()
        assert (typical_qs > capped.upper[shoulder] + LIMIT_TOLERANCE).any()


# --- weak_arm: strength --------------------------------------------------------------------------


def test_a_weak_arm_torque_stays_under_its_cap_and_the_cap_binds():
    arm = dof_indices(RIGHT_ARM)
    caps = WeakArm().body(body_limits()).max_torque[arm]
    assert np.allclose(caps, WeakArm.strength * body_limits().max_torque[arm])
    torques = {}
    for profile in ("typical", "weak_arm"):
        env = dressbench.make_env("fixed", profile=profile, horizon=60, **SMALL)
        env.reset(seed=0)
        torques[profile] = []
        for action in [np.ones(11)] * 30 + [-np.ones(11)] * 30:  # the PD's largest targets
            env.step({HUMAN: action, ROBOT: np.zeros(3)})
            torques[profile].append(np.abs(env.scene.human.torque[arm]))
    weak, strong = np.array(torques["weak_arm"]), np.array(torques["typical"])
    assert (weak <= caps + 1e-9).all()
    assert np.isclose(weak, caps).any()  # it pushes as hard as it can
    assert (strong > caps).any()  # where the typical arm pushes harder


# --- tremor: involuntary motion ------------------------------------------------------------------


def peak_frequency(signal: np.ndarray, dt: float) -> float:
    """The frequency (Hz) of a signal's largest spectral component, its mean removed."""
    spectrum = np.abs(np.fft.rfft(signal - signal.mean()))
    return float(np.fft.rfftfreq(len(signal), dt)[spectrum.argmax()])


def test_the_tremor_peaks_in_its_declared_band_on_its_joints_only():
    frames, dt = 2000, 0.01
    motion = Tremor().involuntary(np.random.default_rng(0), frames, dt)
    assert motion.shape == (frames, N_DOFS)
    shaking = dof_indices(tuple(Tremor.amplitudes))
    assert not np.delete(motion, shaking, axis=1).any()
    low, high = Tremor.band
    for j in shaking:
        assert low <= peak_frequency(motion[:, j], dt) <= high


def test_the_tremor_is_seeded():
    same = [Tremor().involuntary(np.random.default_rng(7), 400, 0.01) for _ in range(2)]
    other = Tremor().involuntary(np.random.default_rng(8), 400, 0.01)
    assert np.array_equal(same[0], same[1])
    assert not np.allclose(same[0], other)


def test_the_body_trembles_in_the_band_by_about_the_declared_amplitude():
    """The real physics, no cloth: a body told to hold still, with and without the tremor."""
    frames, dt = 600, 0.01
    still, shaking = Human(HumanConfig(), dt), Human(HumanConfig(), dt)
    still.reset()
    shaking.reset(involuntary=Tremor().involuntary(np.random.default_rng(0), frames, dt))
    no_force = np.zeros((len(still.body_names), 3))
    moved = []
    for _ in range(frames):
        for body in (still, shaking):
            body.step(no_force, no_force)
        moved.append(shaking.q - still.q)
    moved = np.array(moved)[100:]  # after the first second
    low, high = Tremor.band
    for name, amplitude in Tremor.amplitudes.items():
        j = DOF_NAMES.index(name)
        assert low - 0.5 <= peak_frequency(moved[:, j], dt) <= high + 0.5, name
        assert 0.5 * amplitude < moved[:, j].std() < 2.0 * amplitude, name


def test_a_tremor_episode_is_seeded_through_the_env():
    def arm(seed: int) -> np.ndarray:
        env = dressbench.make_env("fixed", profile="tremor", horizon=10, **SMALL)
        env.reset(seed=seed)
        for _ in range(10):
            env.step({HUMAN: np.zeros(11), ROBOT: np.zeros(3)})
        return env.scene.human.q

    assert np.array_equal(arm(3), arm(3))
    assert not np.allclose(arm(3), arm(4))


# --- a third party's profile ---------------------------------------------------------------------

STIFF = """
from dataclasses import replace

import numpy as np
from dressbench.plugins.profiles import dof_indices


class Stiff:
    api_version = 1

    def body(self, typical):
        upper = typical.upper.copy()
        upper[dof_indices(("elbow_r_flexion",))] = 1.0
        return replace(typical, upper=upper)

    def involuntary(self, rng, frames, dt):
        return None
"""


def test_a_third_party_profile_is_listed_checked_and_used(site):
    install(site, "acme-bodies", "2.0", {PROFILES: {"stiff": "acme_bodies:Stiff"}},
            acme_bodies=STIFF)  # fmt: skip
    plugin = profile_plugins()["stiff"]
    assert (plugin.package, plugin.version, plugin.status) == ("acme-bodies", "2.0", "ok")
    assert ("profile", "stiff", "acme-bodies", "2.0", "ok") in plugin_rows(check=True)
    env = dressbench.make_env("fixed", profile="stiff", horizon=40, **SMALL)
    assert env.scene.human.upper[DOF_NAMES.index("elbow_r_flexion")] == 1.0
    elbow = maximal(env, 40, [np.ones(11)])[:, DOF_NAMES.index("elbow_r_flexion")]
    assert elbow.max() <= 1.0 + LIMIT_TOLERANCE


def test_a_profile_upgraded_while_its_cell_is_running_is_refused(site):
    install(site, "acme-bodies", "2.0", {PROFILES: {"stiff": "acme_bodies:Stiff"}},
            acme_bodies=STIFF)  # fmt: skip
    cell = make_cell("fixed", "passive", profile="stiff", horizon=2, **SMALL)
    Runner(cell)  # as made
    shutil.rmtree(site / "acme_bodies-2.0.dist-info")
    install(site, "acme-bodies", "2.1", {PROFILES: {"stiff": "acme_bodies:Stiff"}})
    refresh()
    with pytest.raises(RuntimeError, match=r"changed since the evaluation started \(.*2\.1"):
        Runner(cell)


# --- a broken profile is one line naming it ------------------------------------------------------

BROKEN_BODIES = {
    "short": ("return replace(typical, upper=typical.upper[:3])",
              "body returned BodyLimits.upper of shape (3,), expected (22,)"),
    "nan": ("return replace(typical, lower=typical.lower * np.nan)",
            "body returned a non-finite BodyLimits.lower"),
    "wider": ("return replace(typical, upper=typical.upper + 1.0)",
              "body returned an upper limit above the typical body's"),
    "nothing": ("return None", "body returned None, expected BodyLimits"),
}  # fmt: skip


def broken_profile(body: str, motion: str = "return None", api_version: int = 1) -> str:
    """A profile module whose ``body`` and ``involuntary`` run the given lines."""
    return (
        "from dataclasses import replace\nimport numpy as np\n\n"
        f"class Profile:\n    api_version = {api_version}\n\n"
        f"    def body(self, typical):\n        {body}\n\n"
        f"    def involuntary(self, rng, frames, dt):\n        {motion}\n"
    )


@pytest.mark.parametrize("name", sorted(BROKEN_BODIES))
def test_a_profile_returning_a_wrong_body_is_one_line_naming_it(site, name):
    body, problem = BROKEN_BODIES[name]
    install(site, "bad-bodies", "0.1", {PROFILES: {name: "bad_body:Profile"}},
            bad_body=broken_profile(body))  # fmt: skip
    with pytest.raises(ValueError) as error:
        dressbench.make_env("fixed", profile=name, horizon=2, **SMALL)
    message = str(error.value)
    assert len(message.splitlines()) == 1
    assert message.startswith(f"capability profile {name!r} from bad-bodies 0.1: {problem}")
    assert profile_problem(name).startswith(problem)
    status = {row[1]: row[4] for row in plugin_rows(check=True)}[name]
    assert status.startswith(f"FAILS CHECK: {problem}")


def test_a_profile_returning_wrong_motion_is_one_line_naming_it(site):
    install(site, "bad-bodies", "0.1", {PROFILES: {"jolt": "bad_motion:Profile"}},
            bad_motion=broken_profile("return typical", "return np.ones((3, 22))"))  # fmt: skip
    env = dressbench.make_env("fixed", profile="jolt", horizon=2, **SMALL)
    with pytest.raises(ValueError) as error:
        env.reset(seed=0)
    assert str(error.value) == (
        "capability profile 'jolt' from bad-bodies 0.1: involuntary returned motion of shape "
        "(3, 22), expected (8, 22): joint accelerations per simulation step"
    )


@pytest.mark.parametrize(
    ("module", "reason"),
    [
        ("raise RuntimeError('no licence')\n", "import failed: RuntimeError: no licence"),
        (broken_profile("return typical", api_version=2),
         "api_version 2 is not supported (this dressbench expects 1)"),
        ("class Profile:\n    api_version = 1\n", "not a profile plugin: missing method body(), "
                                                  "method involuntary()"),
    ],
    ids=["raises-on-import", "api-version", "no-methods"],
)  # fmt: skip
def test_a_profile_that_cannot_load_is_listed_broken_and_refused_in_one_line(site, module, reason):
    install(site, "bad-bodies", "0.1", {PROFILES: {"bad": "bad_load:Profile"}}, bad_load=module)
    assert profile_plugins()["bad"].error == reason
    with pytest.raises(BrokenPluginError) as error:
        load_profile("bad")
    assert str(error.value) == f"profile plugin 'bad' from bad-bodies 0.1 is broken: {reason}"
    with pytest.raises(BrokenPluginError):
        dressbench.make_env("fixed", profile="bad", horizon=2, **SMALL)


def test_an_unknown_profile_is_one_line_with_a_suggestion():
    with pytest.raises(UnknownPluginError) as error:
        dressbench.make_env("fixed", profile="tremr", horizon=2, **SMALL)
    message = str(error.value)
    assert message.startswith("unknown profile 'tremr': did you mean 'tremor'?")
    assert len(message.splitlines()) == 1


# --- a human runs under the profile it was trained for --------------------------------------------


def trained_for(profile: str | None) -> SimpleNamespace:
    """A human as a trained policy declares itself, of ``profile``."""
    return SimpleNamespace(robot="fixed", ablation="complete", actuation="pd", profile=profile,
                           name=f"for-{profile}")  # fmt: skip


def test_a_human_runs_under_its_own_profile():
    env = make_human_env("fixed", human=trained_for("tremor"), horizon=2, **SMALL)
    assert env.env.config.profile == "tremor"
    assert make_cell("fixed", "passive", horizon=2, **SMALL).profile == "typical"


def test_a_human_runs_under_another_profile_only_when_asked_to():
    env = make_human_env("fixed", human=trained_for("tremor"), profile="weak_arm", horizon=2,
                         **SMALL)  # fmt: skip
    assert env.env.config.profile == "weak_arm"


def test_a_human_that_does_not_declare_a_profile_is_typical_and_baselines_run_under_any():
    undeclared = SimpleNamespace(robot="fixed", ablation="complete", name="old")
    assert make_human_env("fixed", human=undeclared, horizon=2, **SMALL).env.config.profile == (
        "typical"
    )
    shipped = load_human("fixed-default-s0")  # a policy file made before profiles
    assert shipped.profile == "typical"
    env = make_human_env("fixed", human="scripted", profile="limited_shoulder", horizon=2, **SMALL)
    assert env.env.config.profile == "limited_shoulder"


# --- cells, identities and training carry the profile ---------------------------------------------


def test_a_typical_cell_keeps_its_identity_and_another_profile_has_its_own():
    typical = make_cell("fixed", "passive", horizon=2, **SMALL)
    tremor = make_cell("fixed", "passive", profile="tremor", horizon=2, **SMALL)
    assert "profile" not in typical.identity and "profile" not in typical.identity["config"]
    version = profile_plugins()["tremor"].version
    assert tremor.identity["profile"] == {"name": "tremor", "distribution": "dressbench",
                                          "version": version}  # fmt: skip
    assert tremor.identity["config"]["profile"] == "tremor"
    assert typical.key != tremor.key
    assert typical.columns["config_id"] != tremor.columns["config_id"]
    assert (typical.columns["profile"], tremor.columns["profile"]) == ("typical", "tremor")


def test_a_leaderboard_scores_its_humans_under_each_profile_asked_each_cell_once():
    asked = ("typical", "tremor", "typical")
    cells = profiles_cells(["fixed"], ["passive", "fixed-default-s0"], profile=asked, horizon=2,
                           **SMALL)  # fmt: skip
    assert sorted((cell.human, cell.profile) for cell in cells) == [
        ("fixed-default-s0", "tremor"), ("fixed-default-s0", "typical"),
        ("passive", "tremor"), ("passive", "typical"),
    ]  # fmt: skip
    one = profiles_cells(["fixed"], ["passive"], profile="weak_arm", horizon=2, **SMALL)
    assert [cell.profile for cell in one] == ["weak_arm"]


def test_a_leaderboard_scores_an_adapted_human_under_its_own_profile_when_that_is_asked(
    policies_on_path, tmp_path
):
    folder = tmp_path / "policies"
    shipped = Path(dressbench.__file__).parent / "policies"
    for name, profile in (("fixed-default-s0", None), ("fixed-tremor-tuned-s0", "tremor")):
        document = json.loads((shipped / "fixed-default-s0.json").read_text())
        document["name"] = name
        if profile:
            document["profile"] = profile
        (folder / f"{name}.json").write_text(json.dumps(document))
        shutil.copy(shipped / "fixed-default-s0.safetensors", folder / f"{name}.safetensors")
    refresh()
    humans = ["fixed-default-s0", "fixed-tremor-tuned-s0"]

    def scored(*asked):
        cells = profiles_cells(["fixed"], humans, profile=asked, horizon=2, **SMALL)
        return sorted((cell.human, cell.profile) for cell in cells)

    assert scored("typical", "weak_arm", "tremor") == [
        ("fixed-default-s0", "tremor"), ("fixed-default-s0", "typical"),
        ("fixed-default-s0", "weak_arm"), ("fixed-tremor-tuned-s0", "tremor"),
    ]  # fmt: skip
    # its own profile not asked: how it does under those asked is the question
    assert scored("typical", "weak_arm") == [
        ("fixed-default-s0", "typical"), ("fixed-default-s0", "weak_arm"),
        ("fixed-tremor-tuned-s0", "typical"), ("fixed-tremor-tuned-s0", "weak_arm"),
    ]  # fmt: skip


def test_a_training_run_records_its_profile_and_a_typical_run_keeps_its_name():
    assert TrainConfig(robot="fixed").run_name == "fixed-complete-trpo-s0"
    weak = TrainConfig(robot="fixed", profile="weak_arm")
    assert weak.run_name == "fixed-complete-weak_arm-trpo-s0"
    assert weak.record()["profile"] == "weak_arm"
    assert TrainConfig.from_dict(weak.record()).profile == "weak_arm"

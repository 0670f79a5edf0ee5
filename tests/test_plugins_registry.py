"""Plugins are found through entry points; broken, duplicate and unknown ones get clear messages.

Every test installs fake distributions (a ``*.dist-info`` folder plus plugin modules) into a
fresh folder on ``sys.path``, so nothing here depends on the built-in plugins.
"""

import importlib.metadata
import os
import subprocess
import sys

import numpy as np
import pytest
from fakes import HUMAN_MODULE, install

from dressbench import plugins

ROBOTS = f"[{plugins.ROBOT_GROUP}]"  # entry_points.txt section headers
HUMANS = f"[{plugins.HUMAN_GROUP}]"

ROBOT_MODULE = """
import numpy as np

class Robot:
    api_version = 1

    def reset(self, rng):
        return np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])

    def act(self, observation):
        return np.zeros(3)
"""


def test_third_party_robot_and_human_are_found_with_package_and_version_and_load_fresh(site):
    install(
        site,
        "acme-dressing",
        "1.2.3",
        {ROBOTS: {"acme_arm": "acme_robot:Robot"}, HUMANS: {"acme_person": "acme_human:Human"}},
        acme_robot=ROBOT_MODULE,
        acme_human=HUMAN_MODULE,
    )
    robot, human = plugins.robot_plugins()["acme_arm"], plugins.human_plugins()["acme_person"]
    for plugin, group in [(robot, plugins.ROBOT_GROUP), (human, plugins.HUMAN_GROUP)]:
        assert (plugin.status, plugin.error, plugin.ok) == ("ok", None, True)
        assert (plugin.package, plugin.version, plugin.group) == ("acme-dressing", "1.2.3", group)
        assert plugin in plugins.all_plugins()
    assert robot.value == "acme_robot:Robot"

    first, second = plugins.load_robot("acme_arm"), plugins.load_robot("acme_arm")
    assert first is not second and isinstance(first, plugins.RobotStrategy)
    assert first.reset(np.random.default_rng(0)).shape == (7,)
    assert first.act(np.zeros(10)).shape == (3,)
    person = plugins.load_human("acme_person")
    assert person is not plugins.load_human("acme_person")
    assert isinstance(person, plugins.HumanPolicy)
    assert (person.robot, person.ablation) == (None, "complete")


def test_a_zero_argument_factory_function_is_a_plugin(site):
    factory = ROBOT_MODULE + "\ndef make():\n    return Robot()\n"
    install(site, "factories", "0.1", {ROBOTS: {"made_arm": "made_robot:make"}}, made_robot=factory)
    assert plugins.robot_plugins()["made_arm"].ok
    assert plugins.load_robot("made_arm") is not plugins.load_robot("made_arm")


@pytest.mark.parametrize(
    ("source", "reason"),
    [
        ("import no_such_module_for_dressbench\n", "ModuleNotFoundError: No module named"),
        ("def broken(:\n", "SyntaxError: "),
        ("raise RuntimeError('no licence\\nsecond line')\n", "RuntimeError: no licence"),
    ],
    ids=["import-error", "syntax-error", "raises-on-import"],
)
def test_failed_import_is_reported_by_name_package_and_version_and_good_ones_still_load(
    site, source, reason
):
    install(
        site,
        "mixed-bag",
        "0.4",
        {ROBOTS: {"bad_arm": "bad_robot:Robot", "good_arm": "good_robot:Robot"}},
        bad_robot=source,
        good_robot=ROBOT_MODULE,
    )
    bad = plugins.robot_plugins()["bad_arm"]
    assert (bad.status, bad.package, bad.version, bad.factory) == (
        "error",
        "mixed-bag",
        "0.4",
        None,
    )
    assert bad.error.startswith("import failed: ") and reason in bad.error
    assert "\n" not in bad.error
    assert plugins.robot_plugins()["good_arm"].ok
    assert plugins.load_robot("good_arm").act(np.zeros(10)).shape == (3,)


@pytest.mark.parametrize(
    ("source", "value", "reason"),
    [
        (ROBOT_MODULE.replace("def act", "def _act"), "Robot", "missing method act()"),
        (ROBOT_MODULE + "Robot.act = 3\n", "Robot", "missing method act()"),
        (ROBOT_MODULE + "ROBOT = 3\n", "ROBOT", "ROBOT is not callable (int)"),
        (ROBOT_MODULE.replace("api_version = 1", "api_version = 2"), "Robot", "api_version 2"),
        (ROBOT_MODULE.replace("api_version = 1", "api_version = '1'"), "Robot", "integer 1"),
        (ROBOT_MODULE.replace("api_version = 1", ""), "Robot", "api_version is missing"),
        (
            ROBOT_MODULE + "\ndef make():\n    raise RuntimeError('no gripper')\n",
            "make",
            "creating an instance failed: RuntimeError: no gripper",
        ),
    ],
    ids=["no-act", "act-not-callable", "not-callable", "api-2", "api-str", "no-api", "init-fails"],
)
def test_wrong_robot_interface_or_api_version_is_reported_with_a_reason(
    site, source, value, reason
):
    install(
        site,
        "wrongbots",
        "2.0",
        {ROBOTS: {"wrong_arm": f"wrong_robot:{value}"}},
        wrong_robot=source,
    )
    plugin = plugins.robot_plugins()["wrong_arm"]
    assert plugin.status == "error" and reason in plugin.error, plugin.error


def test_human_missing_its_attributes_is_reported_naming_them(site):
    source = HUMAN_MODULE.replace("    robot = None\n", "").replace('ablation = "complete"', "")
    install(
        site, "wrongpeople", "1.0", {HUMANS: {"blank": "blank_human:Human"}}, blank_human=source
    )
    error = plugins.human_plugins()["blank"].error
    assert error == "not a human plugin: missing attribute robot, attribute ablation"


def test_duplicate_name_first_package_by_name_wins_and_the_other_names_the_winner(site):
    for package in ["zeta-bots", "alpha-bots"]:
        module = package.replace("-", "_")
        install(
            site,
            package,
            "1.0",
            {ROBOTS: {"twin_arm": f"{module}:Robot"}},
            **{module: ROBOT_MODULE},
        )
    winner = plugins.robot_plugins()["twin_arm"]
    assert (winner.package, winner.status) == ("alpha-bots", "ok")
    (loser,) = [p for p in plugins.all_plugins() if p.name == "twin_arm" and p is not winner]
    assert (loser.package, loser.status) == ("zeta-bots", "error")
    assert loser.error == "duplicate name: also provided by alpha-bots 1.0"
    assert "zeta_bots" not in sys.modules  # a losing duplicate is never imported


def test_dressbench_wins_a_duplicate_name_so_built_ins_keep_their_names(site):
    # a fake "dressbench" distribution, earlier on sys.path, stands in for the built-ins
    install(
        site, "aaa-bots", "1.0", {ROBOTS: {"own_arm": "aaa_robot:Robot"}}, aaa_robot=ROBOT_MODULE
    )
    install(
        site, "dressbench", "9.9", {ROBOTS: {"own_arm": "own_robot:Robot"}}, own_robot=ROBOT_MODULE
    )
    assert plugins.robot_plugins()["own_arm"].package == "dressbench"
    (loser,) = [p for p in plugins.all_plugins() if p.package == "aaa-bots"]
    assert loser.error == "duplicate name: also provided by dressbench 9.9"


def test_one_distribution_seen_twice_is_not_a_duplicate(site, monkeypatch):
    install(
        site, "twice", "1.0", {ROBOTS: {"twice_arm": "twice_robot:Robot"}}, twice_robot=ROBOT_MODULE
    )
    monkeypatch.syspath_prepend(str(site))  # the same folder again, as an editable install can
    plugins.refresh()
    assert [p.status for p in plugins.all_plugins() if p.name == "twice_arm"] == ["ok"]

    # importlib.metadata usually hides the repeat itself; the registry must not rely on that
    entry_points = importlib.metadata.entry_points
    doubled = lambda group: [*entry_points(group=group), *entry_points(group=group)]  # noqa: E731
    monkeypatch.setattr(importlib.metadata, "entry_points", doubled)
    plugins.refresh()
    assert [p.status for p in plugins.all_plugins() if p.name == "twice_arm"] == ["ok"]


def test_unknown_name_raises_with_a_did_you_mean_suggestion_and_the_names_available(site):
    install(
        site, "acme", "1.0", {ROBOTS: {"zebra_arm": "acme_robot:Robot"}}, acme_robot=ROBOT_MODULE
    )
    with pytest.raises(plugins.UnknownPluginError) as caught:
        plugins.load_robot("zebra_amr")
    message = str(caught.value)
    assert isinstance(caught.value, KeyError) and "\n" not in message
    assert message.startswith("unknown robot 'zebra_amr': did you mean 'zebra_arm'?")
    assert "zebra_arm" in message.split("Available: ")[1]
    with pytest.raises(plugins.UnknownPluginError, match="unknown human 'zebra_arm'"):
        plugins.load_human("zebra_arm")


def test_loading_a_broken_plugin_raises_naming_it_its_package_and_the_reason(site):
    install(
        site, "shaky", "0.9", {HUMANS: {"shaky_person": "shaky_human:Human"}}, shaky_human="1/0\n"
    )
    with pytest.raises(plugins.BrokenPluginError) as caught:
        plugins.load_human("shaky_person")
    assert str(caught.value) == (
        "human plugin 'shaky_person' from shaky 0.9 is broken: "
        "import failed: ZeroDivisionError: division by zero"
    )
    assert caught.value.plugin is plugins.human_plugins()["shaky_person"]


SIDE_EFFECT_MODULE = (
    ROBOT_MODULE + "\nimport pathlib\npathlib.Path(__file__).with_suffix('.ran').touch()\n"
)


def test_nothing_is_discovered_or_imported_at_import_dressbench_plugins(site, tmp_path):
    install(
        site,
        "loud",
        "1.0",
        {ROBOTS: {"loud_arm": "loud_robot:Robot"}},
        loud_robot=SIDE_EFFECT_MODULE,
    )
    code = (
        "import sys, dressbench, dressbench.plugins as p; print('loud_robot' in sys.modules); "
        "print(p.robot_plugins()['loud_arm'].status, 'loud_robot' in sys.modules)"
    )
    env = {**os.environ, "PYTHONPATH": str(site)}
    run = subprocess.run(
        [sys.executable, "-c", code], env=env, cwd=tmp_path, capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.split("\n")[:2] == ["False", "ok True"]


def test_discovery_happens_on_first_use_and_is_cached_until_refresh(site):
    install(
        site,
        "loud",
        "1.0",
        {ROBOTS: {"loud_arm": "loud_robot:Robot"}},
        loud_robot=SIDE_EFFECT_MODULE,
    )
    marker = site / "loud_robot.ran"
    assert not marker.exists()
    assert plugins.robot_plugins()["loud_arm"].ok and marker.exists()
    install(
        site, "late", "1.0", {ROBOTS: {"late_arm": "late_robot:Robot"}}, late_robot=ROBOT_MODULE
    )
    assert "late_arm" not in plugins.robot_plugins()
    plugins.refresh()
    assert plugins.robot_plugins()["late_arm"].ok

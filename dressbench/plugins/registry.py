"""Find, check and load robot, human and capability profile plugins advertised through entry
points.

Discovery is lazy: nothing is read or imported until a function here is first called, and the
result is cached until ``refresh()``. Every advertised plugin becomes a ``Plugin`` record, ok or
broken, so that one broken package never hides the others and listings can say what is wrong.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib
import os
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import cast

from dressbench.plugins import protocols
from dressbench.plugins.contract import (
    HUMAN_ATTRIBUTES,
    PLUGIN_METHODS,
    PROFILE_METHODS,
    api_version_problem,
    interface_problem,
)

OK = "ok"
ERROR = "error"
_HOME_PACKAGE = "dressbench"  # its entry points are the built-ins and keep their names
POLICY_FILE_VERSION = "file"  # the version of a trained model found as a policy file


@dataclass(frozen=True)
class Plugin:
    """One advertised plugin: where it comes from, whether it works, and how to create it."""

    name: str
    group: str
    package: str
    version: str
    value: str  # what the entry point names, "module:attr"
    status: str  # OK or ERROR
    error: str | None  # one line: why it is broken
    factory: Callable[[], object] | None  # the loaded class or factory when ok

    @property
    def ok(self) -> bool:
        """Whether the plugin loaded and passed the interface checks."""
        return self.status == OK

    @property
    def from_policy_file(self) -> bool:
        """Whether the plugin is a trained model found as a policy file, not an entry point."""
        return self.version == POLICY_FILE_VERSION and self.package.startswith("policy file ")

    @property
    def origin(self) -> str:
        """``'package version'``, for messages."""
        return f"{self.package} {self.version}"

    @property
    def source(self) -> str:
        """Where the plugin comes from, for messages: ``'package version'``, or the policy file."""
        return self.package if self.from_policy_file else self.origin

    def __reduce__(self) -> tuple[Callable[..., Plugin], tuple[str, ...]]:
        """Pickled without its factory, which the receiving process imports again from
        ``value`` on first use, without discovering the group: a worker makes instances from
        its parent's records, and a node without the plugin's package can still say so."""
        return _unpickled, (*_identity(self), self.status, self.error or "")


def _unpickled(
    name: str, group: str, package: str, version: str, value: str, status: str, error: str
) -> Plugin:
    """A record sent to another process; its factory imports the plugin when first called."""
    record = Plugin(name, group, package, version, value, status, error or None, None)
    if status != OK:
        return record
    return dataclasses.replace(
        record, factory=_Reloaded(name, group, value, record.from_policy_file)
    )


@dataclass(frozen=True)
class _Reloaded:
    """A record's factory in another process: the entry point (or policy file) ``value``,
    imported on the first call."""

    name: str
    group: str
    value: str
    from_policy_file: bool

    def __call__(self) -> object:
        return self._factory()

    @functools.cached_property
    def _factory(self) -> Callable[[], object]:
        if self.from_policy_file:
            from ..policy_file import load_policy

            return functools.partial(load_policy, Path(self.value))
        import importlib.metadata

        return importlib.metadata.EntryPoint(self.name, self.value, self.group).load()


class PluginError(Exception):
    """Base class of the errors raised when a plugin cannot be used."""


class UnknownPluginError(PluginError, KeyError):
    """No plugin of that name is installed in the group."""

    def __str__(self) -> str:
        """One clean line (``KeyError`` would quote the message)."""
        return str(self.args[0])


class BrokenPluginError(PluginError):
    """The plugin is installed but failed to import or does not implement its interface."""

    def __init__(self, message: str, plugin: Plugin) -> None:
        super().__init__(message)
        self.plugin = plugin


@dataclass(frozen=True)
class _Entry:
    """An advertised plugin before loading: its identity and how to import its factory."""

    name: str
    group: str
    package: str
    version: str
    value: str
    load: Callable[[], object]


def _entry_point_entries(group: str) -> list[_Entry]:
    """The plugins that installed distributions advertise under ``group``."""
    import importlib.metadata  # here, not at the top: it costs ~40 ms of import time

    entries = []
    for ep in importlib.metadata.entry_points(group=group):
        dist = ep.dist
        package = (dist.metadata.get("Name") if dist else None) or "<unknown>"
        version = (dist.version if dist else None) or "<unknown>"
        entries.append(_Entry(ep.name, group, package, version, ep.value, ep.load))
    return entries


def shipped_policy_folder() -> Path:
    """The trained humans that ship inside the dressbench distribution (package data)."""
    return Path(__file__).resolve().parents[1] / "policies"


def policy_folders() -> list[Path]:
    """Where trained human models are looked for: ``DRESSBENCH_POLICIES`` (a path list) if
    set, else the shipped ones (``dressbench/policies/``) and ``policies/`` in the working
    directory (a user's own)."""
    configured = os.environ.get("DRESSBENCH_POLICIES")
    if configured:
        folders = [Path(p) for p in configured.split(os.pathsep) if p]
    else:
        folders = [shipped_policy_folder(), Path.cwd() / "policies"]
    unique: dict[Path, None] = {}
    for folder in folders:
        unique.setdefault(folder.resolve(), None)
    return list(unique)


def _policy_file_entries(group: str) -> list[_Entry]:
    """Trained models (``NAME.safetensors`` + ``NAME.json``) as human plugins named NAME."""
    from ..policy_file import list_policies, load_policy

    entries = []
    for folder in policy_folders():
        if os.environ.get("DRESSBENCH_POLICIES") and not folder.is_dir():
            import warnings

            warnings.warn(
                f"DRESSBENCH_POLICIES names {folder}, which is not a folder: no policy is "
                "read from it",
                stacklevel=2,
            )
        for path in list_policies(folder):
            factory = functools.partial(load_policy, path)
            entries.append(
                _Entry(
                    path.stem,
                    group,
                    f"policy file {path}",
                    POLICY_FILE_VERSION,
                    str(path),
                    lambda f=factory: f,
                )
            )
    return entries


@dataclass(frozen=True)
class _Kind:
    """What a group's plugins must provide, and where its plugins come from."""

    group: str
    noun: str
    api_version: int
    attributes: tuple[str, ...]  # what its plugins declare, besides the protocol's methods
    methods: tuple[str, ...] = PLUGIN_METHODS  # the protocol's methods
    # Each source lists a group's plugins: installed entry points, and for humans trained files.
    sources: tuple[Callable[[str], list[_Entry]], ...] = (_entry_point_entries,)


_ROBOT = _Kind(protocols.ROBOT_GROUP, "robot", protocols.ROBOT_API_VERSION, ())
_HUMAN = _Kind(
    protocols.HUMAN_GROUP,
    "human",
    protocols.HUMAN_API_VERSION,
    HUMAN_ATTRIBUTES,
    sources=(_entry_point_entries, _policy_file_entries),
)
_PROFILE = _Kind(
    protocols.PROFILE_GROUP, "profile", protocols.PROFILE_API_VERSION, (), PROFILE_METHODS
)

_cache: dict[str, list[Plugin]] = {}


def _normalize(package: str) -> str:
    """The PEP 503 form of a distribution name, so spellings of one package compare equal."""
    return re.sub(r"[-_.]+", "-", package).lower()


def _one_line(exc: BaseException) -> str:
    """``'Type: first line of the message'``: a reason that fits in a listing."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    return f"{type(exc).__name__}: {lines[0]}" if lines else type(exc).__name__


def _check(kind: _Kind, entry: _Entry) -> tuple[Callable[[], object] | None, str | None]:
    """Import the entry and check one instance of it: ``(factory, None)`` or ``(None, why)``."""
    try:
        factory = entry.load()
    except (Exception, SystemExit) as exc:
        return None, f"import failed: {_one_line(exc)}"
    if not callable(factory):
        kind_of = type(factory).__name__
        return None, f"{entry.value} is not callable ({kind_of}): expected a class or factory"
    if hasattr(factory, "api_version") and (
        problem := api_version_problem(factory, kind.api_version)
    ):
        return None, problem  # an old or future plugin: do not even construct it
    try:
        instance = factory()
    except (Exception, SystemExit) as exc:
        return None, f"creating an instance failed: {_one_line(exc)}"
    try:
        problem = interface_problem(
            instance, kind.noun, kind.api_version, kind.attributes, kind.methods
        )
    except Exception as exc:  # a property that raises while being checked
        return None, f"checking the instance failed: {_one_line(exc)}"
    return (None, problem) if problem else (factory, None)


def _record(kind: _Kind, entry: _Entry) -> Plugin:
    """Load and check one entry into a record."""
    factory, problem = _check(kind, entry)
    status = ERROR if problem else OK
    return Plugin(*_identity(entry), status=status, error=problem, factory=factory)


def _identity(entry: _Entry) -> tuple[str, str, str, str, str]:
    """The fields a record shares with its entry."""
    return entry.name, entry.group, entry.package, entry.version, entry.value


def _precedence(entry: _Entry) -> tuple[bool, str, str]:
    """Sort key among entries sharing a name: dressbench first, then by package name."""
    package = _normalize(entry.package)
    return package != _HOME_PACKAGE, package, entry.value


def _distinct(entries: list[_Entry]) -> list[_Entry]:
    """Drop repeats of one plugin (a distribution seen twice, e.g. an editable install)."""
    seen: dict[tuple[str, str, str], _Entry] = {}
    for entry in entries:
        seen.setdefault((entry.name, entry.value, _normalize(entry.package)), entry)
    return list(seen.values())


def _discover(kind: _Kind) -> list[Plugin]:
    """Records for every plugin of the group, the winner of each name first.

    Losing duplicates are recorded as errors without being imported.
    """
    entries = _distinct([entry for source in kind.sources for entry in source(kind.group)])
    plugins: list[Plugin] = []
    winners: dict[str, Plugin] = {}
    for entry in sorted(entries, key=lambda e: (e.name, _precedence(e))):
        winner = winners.get(entry.name)
        if winner is None:
            plugins.append(winners.setdefault(entry.name, _record(kind, entry)))
        else:
            duplicate = f"duplicate name: also provided by {winner.origin}"
            plugins.append(Plugin(*_identity(entry), status=ERROR, error=duplicate, factory=None))
    return plugins


def _records(kind: _Kind) -> list[Plugin]:
    """The group's records, discovered on first use and cached until ``refresh()``."""
    if kind.group not in _cache:
        _cache[kind.group] = _discover(kind)
    return _cache[kind.group]


def _by_name(kind: _Kind) -> dict[str, Plugin]:
    """The record each name resolves to (a losing duplicate appears only in ``all_plugins()``)."""
    plugins: dict[str, Plugin] = {}
    for plugin in _records(kind):
        plugins.setdefault(plugin.name, plugin)
    return plugins


def refresh() -> None:
    """Forget discovered plugins so the next call re-reads entry points (after installs)."""
    _cache.clear()
    importlib.invalidate_caches()


def robot_plugins() -> dict[str, Plugin]:
    """Every robot plugin name and the record it resolves to, ok or broken."""
    return _by_name(_ROBOT)


def human_plugins() -> dict[str, Plugin]:
    """Every human plugin name and the record it resolves to, ok or broken."""
    return _by_name(_HUMAN)


def profile_plugins() -> dict[str, Plugin]:
    """Every capability profile name and the record it resolves to, ok or broken."""
    return _by_name(_PROFILE)


def human_providers(name: str) -> list[Plugin]:
    """Every human record named ``name``, ok or broken: the one it resolves to first, then its
    losing duplicates."""
    return [plugin for plugin in _records(_HUMAN) if plugin.name == name]


def all_plugins() -> list[Plugin]:
    """Every record of the three groups, losing duplicates included: robots, humans, then
    profiles, each by name."""
    return [*_records(_ROBOT), *_records(_HUMAN), *_records(_PROFILE)]


def _unknown(kind: _Kind, name: str, plugins: dict[str, Plugin]) -> UnknownPluginError:
    """An error for a name nobody provides, with a suggestion and the names that work."""
    import difflib  # only an error message needs it

    usable = [key for key, plugin in sorted(plugins.items()) if plugin.ok]
    close = difflib.get_close_matches(name, list(plugins), n=1)
    hint = f" did you mean {close[0]!r}?" if close else ""
    if usable:
        listing = f"Available: {', '.join(usable)}."
    elif plugins:
        listing = f"Installed but broken: {', '.join(sorted(plugins))}."
    else:
        listing = f"No {kind.noun} plugins are installed."
    return UnknownPluginError(f"unknown {kind.noun} {name!r}:{hint} {listing}")


def _resolve(kind: _Kind, name: str) -> Plugin:
    """The ok record of the named plugin of the group, else its ``PluginError``."""
    plugins = _by_name(kind)
    plugin = plugins.get(name)
    if plugin is None:
        raise _unknown(kind, name, plugins)
    if plugin.factory is None:
        message = f"{kind.noun} plugin {name!r} from {plugin.origin} is broken: {plugin.error}"
        raise BrokenPluginError(message, plugin)
    return plugin


def robot_plugin(name: str) -> Plugin:
    """The record of the robot strategy ``name``, resolved once for all its instances."""
    return _resolve(_ROBOT, name)


def human_plugin(name: str) -> Plugin:
    """The record of the human ``name``, resolved once for all its instances."""
    return _resolve(_HUMAN, name)


def profile_plugin(name: str) -> Plugin:
    """The record of the capability profile ``name``."""
    return _resolve(_PROFILE, name)


def load_robot(name: str) -> protocols.RobotStrategy:
    """A new instance of the robot strategy registered as ``name`` (checked on discovery)."""
    return cast(protocols.RobotStrategy, robot_plugin(name).factory())


def load_human(name: str) -> protocols.HumanPolicy:
    """A new instance of the human policy registered as ``name`` (checked on discovery)."""
    return cast(protocols.HumanPolicy, human_plugin(name).factory())


def load_profile(name: str) -> protocols.CapabilityProfile:
    """A new instance of the capability profile registered as ``name`` (checked on discovery)."""
    return cast(protocols.CapabilityProfile, profile_plugin(name).factory())

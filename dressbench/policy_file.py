"""Trained human policies on disk: safetensors weights plus JSON metadata, loaded without pickle.

A policy named NAME is the pair ``NAME.safetensors`` (the actor MLP, its Gaussian ``log_std`` and
the observation normalisation) and ``NAME.json`` (format, architecture, a checksum of the tensors
and the training metadata). SB3's own ``.zip`` files unpickle arbitrary objects on load, so they
are never shipped; ``load_policy`` rebuilds the actor here, in NumPy, from plain numbers. NumPy
rather than torch because acting is one small matrix-vector product per layer per step, where
torch's per-call overhead dominates, and because loading then never imports torch. See
``docs/policy_files.md``.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import stat
from collections.abc import Callable
from itertools import pairwise
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import safetensors.numpy
from safetensors import SafetensorError

from .files import parse_json
from .observation import HAPTIC_SCALES, NEWTONS, scale_haptics
from .plugins.contract import DEFAULT_ACTUATION
from .plugins.protocols import HUMAN_ACTION_SIZE, TYPICAL_PROFILE
from .scene.actuation import ACTUATIONS

if TYPE_CHECKING:
    pass

FORMAT = "dressbench-policy"
FORMAT_VERSION = 1
ACTIVATION = "tanh"
ACTION_SIZE = HUMAN_ACTION_SIZE
JSON_SUFFIX = ".json"
TENSORS_SUFFIX = ".safetensors"
# Largest files read, checked with os.stat before reading and enforced by a bounded read, so
# that a link to an endless or enormous file never makes a listing read until memory runs out.
# A 64x64 actor is ~100 kB of tensors and ~5 kB of JSON; these limits are far above any MLP.
MAX_TENSORS_BYTES = 256 * 2**20
MAX_JSON_BYTES = 16 * 2**20
# The JSON keys the format owns; every other top-level key is the caller's metadata.
RESERVED_KEYS = ("format", "format_version", "architecture", "obs_normalization", "tensors")


class PolicyFileError(ValueError):
    """A policy file pair that cannot be loaded; the one-line message names the file and why."""


class TrainedPolicy:
    """A trained human policy (the ``HumanPolicy`` protocol): the actor's mean action, in NumPy."""

    api_version: ClassVar[int] = 1

    def __init__(
        self,
        path: Path,
        metadata: dict[str, Any],
        layers: list[tuple[np.ndarray, np.ndarray]],
        obs_mean: np.ndarray,
        obs_var: np.ndarray,
        clip_obs: float,
        epsilon: float,
        log_std: np.ndarray,
        *,
        checksum: str | None = None,
    ) -> None:
        self.path = path  # the .json file
        self.name = path.stem
        self.metadata = metadata
        # the sha256 of the .safetensors, as the JSON records it and load_policy checked it
        self.checksum = checksum
        self.clip_obs = clip_obs
        self.epsilon = epsilon
        self.robot: str | None = metadata["robot"]
        self.ablation: str = metadata["ablation"]
        self.actuation: str = metadata.get("actuation", DEFAULT_ACTUATION)  # what its actions drive
        self.profile: str = metadata.get("profile", TYPICAL_PROFILE)  # the body it learned in
        self.haptics: str = metadata.get("haptics", NEWTONS)  # how it reads the forces
        self.log_std = log_std  # the Gaussian's spread in training; acting uses the mean
        self.layers = layers  # (weight, bias) of each linear layer; the last gives the actions
        self.obs_mean = obs_mean  # the observation normalisation it was trained with
        self.obs_var = obs_var
        self._hidden = layers[:-1]
        self._action_weight, self._action_bias = layers[-1]
        self._obs_std = np.sqrt(obs_var + epsilon)  # as VecNormalize divides

    @property
    def obs_dim(self) -> int:
        """The observation length the policy was trained on."""
        return self.obs_mean.shape[0]

    def reset(self, seed: int | None = None) -> None:
        """Nothing to do: the policy is deterministic and keeps no state between steps."""

    def act(self, observation: np.ndarray) -> np.ndarray:
        """The mean action for a raw (unnormalised) observation, clipped to [-1, 1]."""
        obs = np.asarray(observation, dtype=np.float64)
        if obs.shape != (self.obs_dim,):
            raise ValueError(
                f"policy {self.name!r} expects an observation of shape ({self.obs_dim},), "
                f"got {obs.shape}"
            )
        obs = scale_haptics(obs, self.ablation, self.haptics)
        x = np.clip((obs - self.obs_mean) / self._obs_std, -self.clip_obs, self.clip_obs)
        for weight, bias in self._hidden:
            x = np.tanh(weight @ x + bias)
        return np.clip(self._action_weight @ x + self._action_bias, -1.0, 1.0)

    def __repr__(self) -> str:
        return f"TrainedPolicy({self.name!r}, robot={self.robot!r}, ablation={self.ablation!r})"


def policy_paths(path: str | os.PathLike[str]) -> tuple[Path, Path]:
    """``(NAME.safetensors, NAME.json)`` for either file of a pair or for its stem."""
    path = Path(path)
    if path.suffix in (JSON_SUFFIX, TENSORS_SUFFIX):
        path = path.with_suffix("")
    return path.with_name(path.name + TENSORS_SUFFIX), path.with_name(path.name + JSON_SUFFIX)


# --- saving -------------------------------------------------------------------------------------


def load_policy(path: str | os.PathLike[str]) -> TrainedPolicy:
    """The policy of a file pair, given its ``.json``, its ``.safetensors`` or its stem.

    Never unpickles and never imports torch. Raises ``PolicyFileError`` naming the file when
    either file is missing, unreadable, of another format or version, or inconsistent.
    """
    tensors_path, json_path = policy_paths(path)
    document = _read_document(json_path)
    architecture = document["architecture"]
    tensors = _read_tensors(tensors_path, json_path, document["tensors"])
    _check_tensors(tensors, _expected_shapes(architecture), tensors_path, json_path)
    layers = [
        (tensors[f"{name}.weight"].astype(np.float64), tensors[f"{name}.bias"].astype(np.float64))
        for name in layer_names(len(architecture["hidden_sizes"]))
    ]
    metadata = {key: value for key, value in document.items() if key not in RESERVED_KEYS}
    normalization = document["obs_normalization"]
    return TrainedPolicy(
        json_path,
        metadata,
        layers,
        obs_mean=tensors["obs_mean"].astype(np.float64),
        obs_var=tensors["obs_var"].astype(np.float64),
        clip_obs=float(normalization["clip_obs"]),
        epsilon=float(normalization["epsilon"]),
        log_std=tensors["log_std"].astype(np.float64),
        checksum=document["tensors"]["sha256"],
    )


def _fail(path: Path, reason: str) -> PolicyFileError:
    """The error for a file: ``'<path>: <reason>'`` on one line."""
    return PolicyFileError(f"{path}: {reason}")


def _read_bytes(path: Path, partner: Path, limit: int, size: int | None = None) -> bytes:
    """The file's content, or an error saying it is missing, unreadable, not a regular file,
    larger than ``limit`` bytes or (when ``size`` is given) not ``size`` bytes long.

    The size is checked with ``os.stat`` before anything is read, and the read itself stops
    after ``limit + 1`` bytes, so a link to ``/dev/zero`` or a growing file costs nothing.
    """
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):
            raise _fail(path, f"not a regular file ({_file_kind(info.st_mode)})")
        if info.st_size > limit:
            raise _fail(path, _too_large(info.st_size, limit))
        if size is not None and info.st_size != size:
            raise _fail(path, _wrong_size(info.st_size, size, partner))
        with open(path, "rb") as file:
            data = file.read(limit + 1)
    except FileNotFoundError:
        raise _fail(path, f"missing (a policy is a pair: it goes with {partner.name})") from None
    except OSError as exc:
        raise _fail(path, f"cannot be read: {exc.strerror}") from None
    if len(data) > limit:
        raise _fail(path, _too_large(len(data), limit, "at least "))
    return data


def _too_large(size: int, limit: int, qualifier: str = "") -> str:
    """Why a file is refused for its size."""
    return (
        f"{qualifier}{size} bytes, more than the {limit // 2**20} MiB a policy file may have "
        "(not read)"
    )


def _wrong_size(size: int, expected: int, json_path: Path) -> str:
    """Why a tensors file does not go with its JSON."""
    return (
        f"{size} bytes where {json_path.name} expects {expected} "
        "(truncated, or an interrupted save)"
    )


def _file_kind(mode: int) -> str:
    """What a non-regular file is, in words."""
    for test, kind in (
        (stat.S_ISDIR, "a folder"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a pipe"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return kind
    return "not a plain file"


def _read_document(json_path: Path) -> dict[str, Any]:
    """The parsed and checked JSON of a policy."""
    text = _read_bytes(json_path, policy_paths(json_path)[0], MAX_JSON_BYTES)
    try:
        document = parse_json(text)
    except ValueError as exc:  # JSONDecodeError, UnicodeDecodeError
        raise _fail(json_path, f"not valid JSON ({exc})") from None
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        found = document.get("format") if isinstance(document, dict) else None
        raise _fail(json_path, f"not a dressbench policy (format {found!r}, expected {FORMAT!r})")
    version = document.get("format_version")
    if version != FORMAT_VERSION or isinstance(version, bool):
        raise _fail(
            json_path,
            f"format_version {version!r} is not supported (this dressbench reads {FORMAT_VERSION})",
        )
    problem = _schema_problem(document)
    if problem:
        raise _fail(json_path, problem)
    return document


def _schema_problem(document: dict[str, Any]) -> str | None:
    """What is wrong with a version-1 document's fields, or None."""
    return _fields_problem(document, _FIELDS) or metadata_problem(document)


def metadata_problem(metadata: dict[str, Any]) -> str | None:
    """What is wrong with a policy's training metadata (the ``robot`` and ``ablation`` it must
    name, the optional ``haptics``, ``actuation`` and ``profile``), or None: what loading a
    file checks, and what saving one refuses."""
    return _fields_problem(metadata, _METADATA_FIELDS, _OPTIONAL_FIELDS)


def _fields_problem(
    document: dict[str, Any],
    required: _Fields,
    optional: _Fields = (),
) -> str | None:
    """The first of ``required`` missing or invalid, else of ``optional`` invalid, or None."""
    for keys, valid, wanted in required:
        value = _field(document, keys)
        where = ".".join(keys)
        if value is _MISSING:
            return f"{where} is missing"
        if not valid(value):
            return f"{where} must be {wanted}, found {value!r}"
    for keys, valid, wanted in optional:
        value = _field(document, keys)
        if value is not _MISSING and not valid(value):
            return f"{'.'.join(keys)} must be {wanted}, found {value!r}"
    return None


def _field(document: dict[str, Any], keys: tuple[str, ...]) -> object:
    """The value at a path of nested keys, or ``_MISSING``."""
    value: object = document
    for key in keys:
        if not isinstance(value, dict) or key not in value:
            return _MISSING
        value = value[key]
    return value


def _read_tensors(
    tensors_path: Path, json_path: Path, expected: dict[str, Any]
) -> dict[str, np.ndarray]:
    """The tensors, after checking their size and sha256 against the JSON."""
    blob = _read_bytes(tensors_path, json_path, MAX_TENSORS_BYTES, expected["size"])
    if len(blob) != expected["size"]:  # changed since os.stat
        raise _fail(tensors_path, _wrong_size(len(blob), expected["size"], json_path))
    if hashlib.sha256(blob).hexdigest() != expected["sha256"]:
        raise _fail(
            tensors_path,
            f"checksum does not match {json_path.name} (corrupt, or an interrupted save)",
        )
    try:
        return safetensors.numpy.load(blob)
    except (SafetensorError, TypeError, ValueError) as exc:  # TypeError: a dtype NumPy lacks
        raise _fail(tensors_path, f"not a safetensors file NumPy can read ({exc})") from None


def _expected_shapes(architecture: dict[str, Any]) -> dict[str, tuple[int, ...]]:
    """Every tensor name the architecture needs, with its shape (weights are (out, in))."""
    obs_dim, act_dim = architecture["obs_dim"], architecture["act_dim"]
    sizes = [obs_dim, *architecture["hidden_sizes"], act_dim]
    shapes: dict[str, tuple[int, ...]] = {}
    for name, (n_in, n_out) in zip(layer_names(len(sizes) - 2), pairwise(sizes), strict=True):
        shapes[f"{name}.weight"] = (n_out, n_in)
        shapes[f"{name}.bias"] = (n_out,)
    shapes |= {"log_std": (act_dim,), "obs_mean": (obs_dim,), "obs_var": (obs_dim,)}
    return shapes


def _check_tensors(
    tensors: dict[str, np.ndarray],
    shapes: dict[str, tuple[int, ...]],
    tensors_path: Path,
    json_path: Path,
) -> None:
    """Refuse tensors missing, extra, misshapen (for the JSON's architecture) or not finite."""
    missing = sorted(set(shapes) - set(tensors))
    extra = sorted(set(tensors) - set(shapes))
    if missing or extra:
        listed = "; ".join(
            f"{what}: {', '.join(names)}"
            for what, names in (("missing", missing), ("unexpected", extra))
            if names
        )
        raise _fail(tensors_path, f"tensors do not match {json_path.name} ({listed})")
    for name, shape in shapes.items():
        array = tensors[name]
        if array.shape != shape:
            raise _fail(
                tensors_path,
                f"tensor {name} has shape {array.shape}, the architecture in {json_path.name} "
                f"needs {shape}",
            )
        if not np.issubdtype(array.dtype, np.floating) or not np.isfinite(array).all():
            raise _fail(tensors_path, f"tensor {name} is not finite floating point")
    if (tensors["obs_var"] < 0).any():
        raise _fail(tensors_path, "tensor obs_var has negative variances")


def layer_names(n_hidden: int) -> list[str]:
    """The tensor-name prefixes of the actor's layers: ``pi.0`` ... then ``action``."""
    return [f"pi.{i}" for i in range(n_hidden)] + ["action"]


def is_number(value: object) -> bool:
    """A finite JSON number (not a bool)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _is_positive_int(value: object) -> bool:
    """An integer > 0 (not a bool)."""
    return isinstance(value, int) and not isinstance(value, bool) and value > 0


def _is_sha256(value: object) -> bool:
    """A hex sha256 digest, as ``hashlib`` writes it."""
    return isinstance(value, str) and re.fullmatch("[0-9a-f]{64}", value) is not None


_MISSING = object()
# checked fields, each as (its path of keys, whether a value is valid, what a valid one is)
_Fields = tuple[tuple[tuple[str, ...], Callable[[Any], bool], str], ...]
# The fields of a version-1 JSON after format and format_version.
_FIELDS: _Fields = (
    (
        ("architecture", "hidden_sizes"),
        lambda v: isinstance(v, list) and all(_is_positive_int(size) for size in v),
        "a list of positive integers",
    ),
    (("architecture", "activation"), lambda v: v == ACTIVATION, repr(ACTIVATION)),
    (("architecture", "obs_dim"), _is_positive_int, "an integer > 0"),
    (("architecture", "act_dim"), lambda v: v == ACTION_SIZE, str(ACTION_SIZE)),
    (("obs_normalization", "clip_obs"), lambda v: is_number(v) and v > 0, "a number > 0"),
    (("obs_normalization", "epsilon"), lambda v: is_number(v) and v >= 0, "a number >= 0"),
    (("tensors", "sha256"), _is_sha256, "64 hex digits"),
    (("tensors", "size"), _is_positive_int, "an integer > 0"),
)
# The training metadata the HumanPolicy protocol reads: required, then optional (older files
# leave them out; checked only where present)
_METADATA_FIELDS: _Fields = (
    (("ablation",), lambda v: isinstance(v, str), "a string"),
    (("robot",), lambda v: v is None or isinstance(v, str), "a string or null"),
)
_OPTIONAL_FIELDS: _Fields = (
    (("haptics",), lambda v: v in HAPTIC_SCALES, " or ".join(map(repr, HAPTIC_SCALES))),
    (("actuation",), lambda v: v in ACTUATIONS, " or ".join(map(repr, ACTUATIONS))),
    (("profile",), lambda v: isinstance(v, str), "a capability profile's name"),
)


# --- listing ------------------------------------------------------------------------------------


def list_policies(folder: str | os.PathLike[str]) -> list[Path]:
    """The policy ``.json`` files in ``folder`` (not recursive), sorted; [] if it does not exist.

    A ``.json`` counts when a ``.safetensors`` of the same stem sits beside it or when it declares
    ``"format": "dressbench-policy"``, so a broken policy is still listed (and fails clearly on
    load) while unrelated JSON files are ignored. Tensors are never read.
    """
    folder = Path(folder)
    if not folder.is_dir():
        return []
    candidates = folder.glob("*" + JSON_SUFFIX)
    return sorted(path for path in candidates if path.is_file() and _looks_like_policy(path))


def _looks_like_policy(json_path: Path) -> bool:
    """Whether a JSON file is (meant to be) one half of a policy pair."""
    if policy_paths(json_path)[0].is_file():
        return True
    try:
        document = parse_json(_read_bytes(json_path, json_path, MAX_JSON_BYTES))
    except ValueError:  # PolicyFileError, JSONDecodeError, UnicodeDecodeError
        return False
    return isinstance(document, dict) and document.get("format") == FORMAT

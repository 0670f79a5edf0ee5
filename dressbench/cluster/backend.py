"""Where a command's tasks run: this machine's processes, or a Ray cluster at an address."""

from __future__ import annotations

import re
from dataclasses import dataclass

BACKENDS = ("local", "ray")
# Ray's own forms: "auto" (the cluster this machine joined), HOST:PORT of a head's GCS,
# ray://HOST:PORT of a Ray Client server.
ADDRESS = re.compile(r"auto|(ray://)?[^\s:/]+:\d{1,5}")


class ClusterError(Exception):
    """Ray is missing or unreachable, or a task could not run on a node: one line says why."""


@dataclass(frozen=True)
class Backend:
    """``local`` (processes of this machine) or ``ray``; ``address`` None starts a local Ray
    instance, ``auto`` or ``HOST:PORT`` or ``ray://HOST:PORT`` joins a running cluster."""

    name: str = "local"
    address: str | None = None

    def __post_init__(self) -> None:
        if self.name not in BACKENDS:
            raise ValueError(f"backend must be one of {', '.join(BACKENDS)}, got {self.name!r}")
        if self.address is None:
            return
        if self.name != "ray":
            raise ValueError(f"an address is for the ray backend, not {self.name!r}")
        if not ADDRESS.fullmatch(self.address):
            raise ValueError(
                f"address must be auto, HOST:PORT or ray://HOST:PORT, got {self.address!r}"
            )

    @property
    def is_ray(self) -> bool:
        """Whether the tasks go to Ray."""
        return self.name == "ray"


def first_line(error: BaseException) -> str:
    """The first non-empty line of an exception's message, or its type's name."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    return lines[0] if lines else type(error).__name__

"""A generated block of a Markdown doc: the text between two HTML comments that a command
rewrites from the results it wrote, so that the numbers a doc states are those computed (the
README's strategy table, docs/reproduction.md's verdicts)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from ..files import read_untrusted, write_text


@dataclass(frozen=True)
class DocBlock:
    """The block named ``name`` between the lines ``begin`` and ``end`` of a doc."""

    name: str
    begin: str
    end: str

    def read(self, doc: str | os.PathLike) -> str:
        """The block's text (ValueError in one line for a doc without the markers)."""
        _, block, _ = self._split(doc)
        return block.strip("\n") + "\n"

    def write(self, doc: str | os.PathLike, text: str) -> None:
        """Replace the block's text by ``text``; the rest of the doc is kept as it is."""
        head, _, tail = self._split(doc)
        write_text(Path(doc), f"{head}{self.begin}\n{text}{self.end}{tail}")

    def _split(self, doc: str | os.PathLike) -> tuple[str, str, str]:
        """The doc's text before the block, the block, and the text after it."""
        text = read_untrusted(doc, "a Markdown doc").decode("utf-8", errors="replace")
        if self.begin not in text or self.end not in text.split(self.begin, 1)[1]:
            raise ValueError(f"{doc} has no {self.name} block ({self.begin!r} ... {self.end!r})")
        head, rest = text.split(self.begin, 1)
        block, tail = rest.split(self.end, 1)
        return head, block, tail

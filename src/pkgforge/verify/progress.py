"""colcon-style status lines on a terminal; nothing at all when not on one."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO


class Progress:
    def __init__(self, enabled: bool | None = None, stream: TextIO | None = None) -> None:
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.start = time.monotonic()
        self.shown = False

    def show(self, text: str) -> None:
        if self.enabled:
            self.stream.write(f"\r\x1b[K[{time.monotonic() - self.start:5.1f}s] {text}")
            self.stream.flush()
            self.shown = True

    def counter(self, what: str, total: int) -> Callable[[], None]:
        """A callback that shows `what done/total` each time one more is done."""
        done = [0]

        def tick() -> None:
            done[0] += 1
            self.show(f"{what} {done[0]}/{total}")

        return tick

    def clear(self) -> None:
        if self.enabled and self.shown:
            self.stream.write("\r\x1b[K")
            self.stream.flush()

"""A progress bar: tqdm's when it is installed, a plain text bar otherwise."""

from __future__ import annotations

import sys
import time
from typing import TextIO


class ProgressBar:
    """A bar from 0 to 1 with a message, drawn on ``stream`` (stderr).

    Uses ``tqdm`` when it can be imported (and ``plain`` is false), else a
    one-line text bar redrawn at most ten times a second.
    """

    def __init__(self, description: str = "", stream: TextIO | None = None, plain: bool = False) -> None:
        self._stream = stream if stream is not None else sys.stderr
        self._description = description
        self._tqdm = None
        self._last_draw = 0.0
        self._fraction = 0.0
        self._message = ""
        if not plain:
            try:
                from tqdm.auto import tqdm  # type: ignore[import-untyped, unused-ignore]
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self._tqdm = tqdm(
                    total=1000,
                    desc=description or None,
                    file=self._stream,
                    bar_format="{l_bar}{bar:30}| [{elapsed}]{postfix}",
                )

    def update(self, fraction: float, message: str = "") -> None:
        """Moves the bar to ``fraction`` (0..1) and shows ``message``."""
        fraction = min(max(float(fraction), 0.0), 1.0) if fraction == fraction else 0.0
        self._fraction, self._message = fraction, message
        if self._tqdm is not None:
            self._tqdm.n = int(fraction * 1000)
            self._tqdm.set_postfix_str(message, refresh=False)
            self._tqdm.refresh()
            return
        now = time.monotonic()
        if now - self._last_draw >= 0.1:
            self._last_draw = now
            self._draw()

    def _draw(self, end: str = "") -> None:
        filled = int(self._fraction * 30)
        bar = "#" * filled + "-" * (30 - filled)
        head = f"{self._description}: " if self._description else ""
        self._stream.write(f"\r{head}[{bar}] {self._fraction * 100:5.1f}% {self._message}{end}")
        self._stream.flush()

    def finish(self) -> None:
        """Moves the bar to the end (the work is done), keeping the message."""
        self.update(1.0, self._message)

    def close(self) -> None:
        """Draws the final state and ends the line."""
        if self._tqdm is not None:
            self._tqdm.close()
        else:
            self._draw(end="\n")

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

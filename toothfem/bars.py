"""Progress of the long runs, on stderr: a bar on a terminal; elsewhere (a log, a pipe, CI)
one line per finished stage, ``progress: <stage>: <count> <unit>s in <time> s``, so a log
says what ran and how long without being flooded with redraws; a stage that asks for it
(``every_s``) also writes a line inside itself at most that often, so a long stage's log
says how far it got."""
from __future__ import annotations

import contextlib
import sys
import time

#: How a stage line begins (a reader of stderr tells progress from a refusal by it).
PROGRESS_PREFIX = "progress: "


def bar(iterable=None, *, enabled: bool = True, **kwargs):
    """A tqdm bar on a terminal, else a :class:`StageLine`.

    Parameters
    ----------
    iterable : iterable, optional
        What to wrap.
    enabled : bool
        False: nothing shown at all.
    **kwargs
        Go to :class:`tqdm.tqdm` (``total``, ``desc``, ``unit``, ``initial``); ``every_s``
        to :class:`StageLine` only (a terminal's bar redraws by itself).

    Returns
    -------
    tqdm.tqdm or StageLine
        Either iterates ``iterable`` and has ``update``, ``close`` and the context manager.
    """
    stream = kwargs.get("file") or sys.stderr
    if enabled and not _is_terminal(stream):
        return StageLine(iterable, stream=stream, **kwargs)
    from tqdm import tqdm

    kwargs.pop("every_s", None)
    return tqdm(iterable, disable=not enabled, **kwargs)


def _is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):       # closed or not a file
        return False


class StageLine:
    """A stage's progress off a terminal: counts silently, and writes one line when the
    stage ends (its iterable exhausted, or ``close``); nothing when it is left by an
    exception (the error says what happened).

    Parameters
    ----------
    iterable : iterable, optional
        What to wrap.
    stream : file, optional
        Where the line goes (default stderr).
    desc, unit : str
        The stage's name and what it counts.
    total : int, optional
        How many there are to do.
    initial : int
        How many are done already (a resumed run).
    every_s : float, optional
        Also a line inside the stage, on a count or a postfix that comes at least this
        many seconds after the stage's start or its last line (None: the end's only).
    """

    def __init__(self, iterable=None, *, stream=None, desc: str = "", unit: str = "it",
                 total=None, initial: int = 0, every_s: float | None = None, **_ignored):
        self.iterable = iterable
        self.stream = stream or sys.stderr
        self.desc, self.unit, self.total = desc or "stage", unit, total
        self.n = int(initial)
        self._start = self._said = time.perf_counter()
        self.every_s = every_s
        self._closed = False
        self.postfix = ""

    def __iter__(self):
        for item in self.iterable:
            yield item
            self.n += 1
        self.close()

    def update(self, n: int = 1) -> None:
        """Count ``n`` more done.

        Parameters
        ----------
        n : int
        """
        self.n += n
        self._interim()

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """What the stage's line ends with (tqdm's postfix).

        Parameters
        ----------
        text : str
        refresh : bool
            tqdm's (ignored: a line is written by ``every_s``).
        """
        self.postfix = str(text)
        self._interim()

    def _interim(self) -> None:
        """A line inside the stage where ``every_s`` has passed since the last."""
        if self.every_s is None or self._closed:
            return
        now = time.perf_counter()
        if now - self._said >= self.every_s:
            self._said = now
            self._line(" so far")

    def close(self) -> None:
        """Write the stage's line (once)."""
        if self._closed:
            return
        self._closed = True
        self._line("")

    def _line(self, so_far: str) -> None:
        of = f" of {self.total}" if self.total is not None and self.total != self.n else ""
        unit = self.unit if self.n == 1 else self.unit + "s"
        with contextlib.suppress(OSError, ValueError):  # a closed or broken stderr: progress only
            print(f"{PROGRESS_PREFIX}{self.desc}: {self.n}{of} {unit}{so_far} in "
                  f"{time.perf_counter() - self._start:.1f} s"
                  + (f" ({self.postfix})" if self.postfix else ""), file=self.stream, flush=True)

    def __enter__(self):
        return self

    def __exit__(self, kind, value, tb):
        if kind is None:
            self.close()
        else:
            self._closed = True
        return False


@contextlib.contextmanager
def stage(desc: str, *, stream=None):
    """A stage without a count (a factorisation, a system solve, a report): on a terminal
    ``<desc> ...`` when it starts; everywhere ``progress: <desc>: done in <time> s`` when it
    ends (nothing when it is left by an exception: the error says what happened), so that
    no stretch of a run is silent.

    Parameters
    ----------
    desc : str
        The stage's name.
    stream : file, optional
        Where the lines go (default stderr).

    Yields
    ------
    None
    """
    stream = stream or sys.stderr
    start = time.perf_counter()
    with contextlib.suppress(OSError, ValueError):
        if _is_terminal(stream):
            print(f"{desc} ...", file=stream, flush=True)
    yield
    with contextlib.suppress(OSError, ValueError):   # a closed or broken stderr
        print(f"{PROGRESS_PREFIX}{desc}: done in {time.perf_counter() - start:.1f} s",
              file=stream, flush=True)


def no_stage(desc: str):
    """:func:`stage`'s silent stand-in (an API call without progress).

    Parameters
    ----------
    desc : str

    Returns
    -------
    contextlib.AbstractContextManager
    """
    return contextlib.nullcontext()

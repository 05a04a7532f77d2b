"""Progress bars of the long runs, on stderr: shown on a terminal, silent where stderr is a
file or a pipe (a log or CI output is not flooded with redraws)."""
from __future__ import annotations


def bar(iterable=None, *, enabled: bool = True, **kwargs):
    """A tqdm bar that shows only on a terminal.

    Parameters
    ----------
    iterable : iterable, optional
        What to wrap.
    enabled : bool
        False: no bar at all.
    **kwargs
        Go to :class:`tqdm.tqdm` (``total``, ``desc``, ``unit``).

    Returns
    -------
    tqdm.tqdm
        Disabled off a terminal (tqdm's ``disable=None``) or when not ``enabled``.
    """
    from tqdm import tqdm

    return tqdm(iterable, disable=None if enabled else True, **kwargs)

"""One small module per CLI subcommand; each calls only the public API."""


def json_default(x):
    """``json.dumps``'s ``default`` of the commands: numpy arrays as lists, numpy scalars
    as Python numbers, anything else as its text.

    Parameters
    ----------
    x : object

    Returns
    -------
    list, int, float, bool or str
    """
    import numpy as np

    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, (np.floating, np.integer, np.bool_)):
        return x.item()
    return str(x)

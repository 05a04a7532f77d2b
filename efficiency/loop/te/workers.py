"""The TE's two directions of rotation solved side by side: one process per direction, each
with its own :class:`~.model.RecordingModel` of the case (:meth:`RecordingModel.runs`), so a
fit's model evaluation takes about half the time on two processors. Each process keeps its
direction's states from call to call (the warm starts of :meth:`RecordingModel.runs`), so
the numbers are those of one process solving both directions in turn, bit for bit.

Each process is this module run by the same interpreter (``python -m``, the parent's
``sys.path``; not :mod:`multiprocessing`, whose ``spawn`` runs the caller's main script
again and whose ``fork`` copies a parent's threads' locks), started at the first call and
stopped by :meth:`DirectionWorkers.close`; requests and answers are pickles over its
standard input and output (what it prints goes to standard error). It ignores SIGINT (the
parent stops it) and ends by itself when its input closes (the parent killed).
"""
from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys

#: Seconds a worker is given to end after it is asked to, before it is terminated.
JOIN_TIMEOUT_S = 5.0
#: The directions, in the order :meth:`DirectionWorkers.runs` returns them.
DIRECTIONS = (1, -1)


class WorkerEnded(RuntimeError):
    """A direction's process ended without an answer (killed, out of memory)."""


def serve(inp, out) -> None:
    """A worker's loop: (model class, case, options, direction) first (the class pickled
    by its name: this module imports no model), then (effects, torques, samples) in, that
    direction's runs out (or the exception that stopped them), until None or the end of
    the input.

    Parameters
    ----------
    inp, out : binary files
        The requests and the answers.
    """
    try:
        make, case, options, sign = pickle.load(inp)
        model = None
        while True:
            msg = pickle.load(inp)
            if msg is None:
                return
            effects, torques, samples = msg
            answer: tuple
            try:
                model = model or make(case, **options)
                answer = ("ok", model.runs(effects, torques, sign, samples=samples))
            except Exception as exc:      # noqa: BLE001 - handed to the parent, raised there
                answer = ("error", exc)
            pickle.dump(answer, out, protocol=pickle.HIGHEST_PROTOCOL)
            out.flush()
    except (EOFError, OSError):           # the parent is gone
        return


def main() -> int:
    """The worker process: SIGINT ignored, the answers on the original standard output,
    anything printed on standard error.

    Returns
    -------
    int
        0.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    out = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    serve(sys.stdin.buffer, out)
    return 0


class DirectionWorkers:
    """Two processes, forward and backward, each solving its direction of the case's TE.

    Parameters
    ----------
    make : type
        The model's class (:class:`~.model.RecordingModel`; its ``runs``), pickled by name.
    case : toothfem.case.Case
        A loaded case (pickled to each process).
    options : dict
        The class's keywords (positions, samples, cache, system options), the same in each
        process.
    """

    def __init__(self, make, case, options: dict):
        self.make = make
        self.case = case
        self.options = dict(options)
        self._procs: list = []

    def _start(self) -> None:
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
        for sign in DIRECTIONS:
            proc = subprocess.Popen([sys.executable, "-m", __spec__.name],  # noqa: S603
                                    stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
            self._procs.append(proc)
            self._send(proc, (self.make, self.case, self.options, sign))

    @staticmethod
    def _send(proc, msg) -> None:
        pickle.dump(msg, proc.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        proc.stdin.flush()

    def runs(self, effects, torques, samples) -> tuple:
        """Each direction's :meth:`RecordingModel.runs`, solved at once.

        Parameters
        ----------
        effects : Effects
        torques : sequence of float
            Checked output torques [N m].
        samples : int or None

        Returns
        -------
        tuple
            (forward runs, backward runs).

        Raises
        ------
        Exception
            What a direction's solve raised (the forward one's first).
        WorkerEnded
            Where a process ended without an answer.
        """
        if not self._procs:
            self._start()
        try:
            for proc in self._procs:
                self._send(proc, (effects, list(torques), samples))
        except OSError:
            pass                          # said below, by the process that ended
        answers = []
        for proc, sign in zip(self._procs, DIRECTIONS):
            try:
                answers.append(pickle.load(proc.stdout))
            except (EOFError, OSError, pickle.UnpicklingError):
                code = proc.poll()
                self.close()
                raise WorkerEnded(f"the TE's {'forward' if sign > 0 else 'backward'} process "
                                  f"ended without an answer (exit code {code})") from None
        for kind, value in answers:
            if kind == "error":
                raise value
        return tuple(value for _, value in answers)

    def close(self) -> None:
        """Stop the processes (asked first, then terminated)."""
        for proc in self._procs:
            try:
                self._send(proc, None)
                proc.stdin.close()
            except OSError:
                pass
        for proc in self._procs:
            try:
                proc.wait(JOIN_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                proc.terminate()
                proc.wait(JOIN_TIMEOUT_S)
            proc.stdout.close()
        self._procs = []


if __name__ == "__main__":
    raise SystemExit(main())

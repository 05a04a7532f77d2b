"""The steady forced response of the linearised system model by harmonic balance
(docs/dynamics.md, "Dynamic response at speed").

The reducer turning at a constant input speed carries its static path u_s(t): at each
crank angle the equilibrium of the system model under the output torque, input held at
that angle (the transmission error and every body's deflection, from the FE tables over the
meshing cycle: the time-varying mesh stiffness under load). Linearised about that path,
f(x, t) ~ Q + K(t) (x - u_s(t)), the motion x obeys

    M x'' + C x' + K(t) (x - u_s(t)) = 0,

the static TE as excitation through the mesh stiffness (the classic model of gear
dynamics: H.N. Oezgueven & D.R. Houser, "Mathematical models used in gear dynamics - a
review", J. Sound Vib. 121 (1988) 383-411). With K(t) taken at its mean over the meshing
cycle (the parametric part (K(t) - K_mean)(x - u_s) is a product of the stiffness's
variation and the dynamic deviation, second order below resonance; its size is each
mode's range over the positions, which ``toothfem modes`` prints), each harmonic of the
path at frequency W gives

    (K - W^2 M + i W C) x_h = K u_s,h,

solved in the modes of (K, M) with modal damping C = M Phi diag(2 zeta w_i) Phi^T M: one
linear solve per harmonic and speed, exact for the linear time-invariant system (harmonic
balance needs no transient to die out, unlike a time integration, and a sweep of 50 speeds
is one matrix product per speed). At W -> 0, x_h -> u_s,h: the static TE.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg

from ...errors import CaseError


class ModalSystem:
    """(K, M) with the massless coordinates condensed (exact statically) and modal damping
    of ratio zeta on every flexible mode.

    Parameters
    ----------
    k, m : numpy.ndarray, shape (n, n)
        Stiffness and mass on the same coordinates (m's zero rows: massless).
    zeta : float
        The modal damping ratio, in [0, 1).
    """

    def __init__(self, k, m, zeta: float):
        if not 0.0 <= zeta < 1.0:
            raise CaseError(f"damping_ratio = {zeta!r}: in [0, 1)")
        self.k, self.m = np.asarray(k, float), np.asarray(m, float)
        self.zeta = float(zeta)
        self.heavy = np.diag(self.m) > 0
        light = ~self.heavy
        h = self.heavy
        self._kss = self.k[np.ix_(light, light)]
        self._ksm = self.k[np.ix_(light, h)]
        kmm = self.k[np.ix_(h, h)]
        if light.any():
            kmm = kmm - self.k[np.ix_(h, light)] @ np.linalg.solve(self._kss, self._ksm)
        d = 1.0 / np.sqrt(np.diag(self.m)[h])
        w2, phi = scipy.linalg.eigh(0.5 * (kmm + kmm.T) * d[:, None] * d[None, :],
                                    self.m[np.ix_(h, h)] * d[:, None] * d[None, :])
        self.w2 = np.maximum(w2, 0.0)
        self.phi = phi * d[:, None]                  # mass-normalised, heavy coordinates

    def response(self, force_hat, omega) -> np.ndarray:
        """The steady response x_h to forces F_h e^(i W_h t) (on every coordinate).

        Parameters
        ----------
        force_hat : array_like, shape (H, n)
            Complex amplitudes of the forces [N, N m].
        omega : array_like, shape (H,)
            W_h [rad/s], >= 0 (0: the static solve).

        Returns
        -------
        numpy.ndarray, shape (H, n), complex
        """
        f = np.atleast_2d(np.asarray(force_hat, complex))
        w = np.atleast_1d(np.asarray(omega, float))
        h, light = self.heavy, ~self.heavy
        fm = f[:, h]
        if light.any():               # the massless coordinates' forces carried over
            fm = fm - f[:, light] @ np.linalg.solve(self._kss, self._ksm)
        wi = np.sqrt(self.w2)
        q = fm @ self.phi                                                # (H, modes)
        den = self.w2[None, :] - w[:, None] ** 2 + 2j * self.zeta * wi[None, :] * w[:, None]
        static = w == 0
        if np.any(den[~static] == 0):
            raise CaseError("an undamped resonance or a rigid motion at a forcing frequency")
        den[static] = np.where(self.w2 > 0, self.w2, np.inf)
        xm = (q / den) @ self.phi.T
        x = np.zeros((f.shape[0], self.k.shape[0]), complex)
        x[:, h] = xm
        if light.any():
            x[:, light] = np.linalg.solve(self._kss, (f[:, light] - xm @ self._ksm.T).T).T
        return x


def harmonics_of(path) -> np.ndarray:
    """The complex amplitudes of a periodic path sampled evenly over its period:
    path(t) = Re sum_h X_h e^(i h theta), h = 0 .. N//2.

    Parameters
    ----------
    path : array_like, shape (N, n)

    Returns
    -------
    numpy.ndarray, shape (N//2 + 1, n), complex
    """
    p = np.asarray(path, float)
    n = p.shape[0]
    x = np.fft.rfft(p, axis=0) / n
    x[1:] *= 2.0
    if n % 2 == 0:
        x[-1] /= 2.0
    return x


def path_of(harmonics, samples: int) -> np.ndarray:
    """The inverse of :func:`harmonics_of`.

    Parameters
    ----------
    harmonics : array_like, shape (N//2 + 1, n), complex
    samples : int
        N.

    Returns
    -------
    numpy.ndarray, shape (N, n)
    """
    x = np.array(harmonics, complex)
    x[1:] /= 2.0
    if samples % 2 == 0:
        x[-1] *= 2.0
    return np.fft.irfft(x * samples, n=samples, axis=0)

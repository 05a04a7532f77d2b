"""Loaded transmission error over the drive's full period and the torque split between
its members: the records the system model fills (:func:`toothfem.fem.system.datasheet.
system_te`), the Fourier fill over the sampled pitches, and the even split that a layout's
symmetry gives without a solve (docs/stiffness.md).

The full period. A cycloid disc's contacts at pin pitch m are those of pitch 0 moved m
lobes on against the disc's holes, so the mesh repeats after Za / gcd(Za, s) pitches (s the
hole pattern's symmetry; ``Drive.full_period_pitches``), not after one. The period is
sampled: the system at ``samples`` pitches m_q spread over the period (one factorisation of
each disc's FE tables, kept in the disk cache) gives the twist at every position of those
pitches; a least-squares Fourier series in m through the samples fills the other pitches
(exact for the hole-induced variation up to the order (samples - 1) / 2 per full period;
the pin-pitch ripple comes from each pitch's own positions).

The even split. Where every member stands at the first member's configuration
(``Drive.member_offsets`` all equal) and the shared crankshafts load each member alike
(equal row sums of their coupled compliance, ``Drive.coupled_compliance``), T/M on each
member is the split at every position, exactly, and nothing is solved.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import CaseError, check_range
from .twist import ARCSEC

#: Default pitches sampled over the full period, and positions per pitch of each.
DEFAULT_SAMPLES, DEFAULT_PER_PITCH = 6, 12
#: Harmonics listed (the largest, sorted by order).
HARMONICS_LISTED = 8


@dataclass(frozen=True, kw_only=True)
class LoadedTE:
    """Loaded TE at one output torque over the full period (N = pitches x per_pitch)."""
    output_torque_Nm: float
    crank_angle_rad: np.ndarray      # (N,)
    output_angle_rad: np.ndarray     # (N,)
    te_rad: np.ndarray               # (N,) output twist (the lag of the output), total
    mesh_rad: np.ndarray             # (N,) the first member's mesh rotation at the even share
    sampled_pitches: tuple
    per_pitch: int
    full_period_pitches: int
    orders_per_output_rev: np.ndarray   # (N//2,) order of each harmonic h = 1..
    amplitude_arcsec: np.ndarray        # (N//2,)

    @property
    def peak_to_peak_arcsec(self) -> float:
        return float(np.ptp(self.te_rad) / ARCSEC)

    @property
    def rms_arcsec(self) -> float:
        return float(np.sqrt(np.mean((self.te_rad - self.te_rad.mean()) ** 2)) / ARCSEC)

    def harmonics(self, count: int = HARMONICS_LISTED) -> list:
        """The ``count`` largest harmonics, by order.

        Parameters
        ----------
        count : int
            How many.

        Returns
        -------
        list of dict
            {"order_per_output_rev": float, "amplitude_arcsec": float}, by rising order.
        """
        top = np.argsort(self.amplitude_arcsec)[::-1][:count]
        return [{"order_per_output_rev": float(self.orders_per_output_rev[i]),
                 "amplitude_arcsec": float(self.amplitude_arcsec[i])} for i in sorted(top)]

    def summary(self) -> dict:
        """The figures of the data sheet's TE row.

        Returns
        -------
        dict
            te_torque_Nm [N m], mean, peak-to-peak and RMS [arcsec], the period's pitches, the
            positions per pitch and :meth:`harmonics`.
        """
        return {"te_torque_Nm": self.output_torque_Nm,
                "te_mean_arcsec": float(self.te_rad.mean() / ARCSEC),
                "te_peak_to_peak_arcsec": self.peak_to_peak_arcsec,
                "te_rms_arcsec": self.rms_arcsec,
                "te_full_period_pitches": self.full_period_pitches,
                "te_sampled_pitches": list(self.sampled_pitches),
                "te_positions_per_pitch": self.per_pitch,
                "te_harmonics": self.harmonics()}


@dataclass(frozen=True, kw_only=True)
class MemberSplit:
    """The output torque's split between the members over the full period: ``share[j, g]``
    = T_j / T at grid position g (the first member's crank angle), member j standing at
    the first member's configuration ``g + offsets[j]``."""
    share: np.ndarray                # (M, N) T_j / T
    crank_angle_rad: np.ndarray      # (N,)
    output_torque_Nm: float
    offsets: tuple                   # (M,) ``Drive.member_offsets(per_pitch)``
    per_pitch: int
    even_by_layout: bool             # True: even at every position by symmetry, not solved

    @property
    def load_factor(self) -> float:
        """Largest member torque over the even share (the seed's disc load factor)."""
        return float(np.max(self.share) * self.share.shape[0])

    def ratio_by_position(self) -> np.ndarray:
        """Each member's torque over the even share T/M at each position of one pitch, in
        its own configuration, averaged over the full period's pitches.

        Returns
        -------
        numpy.ndarray, shape (M, per_pitch)
            Member j at the first member's configuration p + (any whole pitch); 1 for the
            even split.
        """
        m, n = self.share.shape
        own = np.stack([np.roll(self.share[j], self.offsets[j]) for j in range(m)])
        return m * own.reshape(m, n // self.per_pitch, self.per_pitch).mean(axis=1)

    def summary(self) -> dict:
        """The figures of the data sheet's member-split row.

        Returns
        -------
        dict
            Largest, smallest and mean share per member [-], the load factor, and how the
            split was found.
        """
        return {"member_share_max": float(np.max(self.share)),
                "member_share_min": float(np.min(self.share)),
                "member_share_mean": [float(x) for x in self.share.mean(axis=1)],
                "member_load_factor_fe": self.load_factor,
                "member_split_even_by_layout": self.even_by_layout}


def sampled_pitches(full_period: int, samples: int) -> tuple:
    """Pitches m_q = round(q k / Q), q < Q, of the cycle solvers over a full period of k.

    Parameters
    ----------
    full_period : int
        k, pitches in the full period.
    samples : int
        Q, cycle solvers wanted (at most k are used).

    Returns
    -------
    tuple of int
        The distinct pitches, sorted.
    """
    q = min(int(samples), full_period)
    return tuple(sorted({int(round(i * full_period / q)) % full_period for i in range(q)}))


def fourier_fill(pitches, values, full_period: int) -> np.ndarray:
    """Values at every pitch of the period from those at ``pitches``: the least-squares
    Fourier series in the pitch of order (Q - 1) // 2 (period k).

    Parameters
    ----------
    pitches : sequence of int
        The Q sampled pitches.
    values : array_like, shape (Q, n)
        Values at them (any unit).
    full_period : int
        k.

    Returns
    -------
    numpy.ndarray, shape (k, n)
        Values at pitches 0..k-1 (the samples themselves when Q = k).
    """
    values = np.asarray(values, float)
    if len(pitches) == full_period:
        return values[np.argsort(pitches)]
    order = (len(pitches) - 1) // 2

    def basis(m):
        m = np.asarray(m, float)[:, None]
        h = np.arange(1, order + 1)[None, :]
        a = 2 * math.pi * h * m / full_period
        return np.concatenate([np.ones((m.shape[0], 1)), np.cos(a), np.sin(a)], axis=1)

    coef, *_ = np.linalg.lstsq(basis(pitches), values, rcond=None)
    return basis(np.arange(full_period)) @ coef


def harmonic_amplitudes(signal, full_period_output_rad: float):
    """Spectrum of a signal sampled evenly over one full period of ``full_period_output_rad``
    output angle: harmonic h has amplitude 2 |X_h| / N and order h 2 pi / (output angle of
    the period).

    Parameters
    ----------
    signal : array_like, shape (N,)
        The samples (any unit).
    full_period_output_rad : float
        Output angle of the period [rad].

    Returns
    -------
    orders : numpy.ndarray, shape (N//2,)
        Orders per output revolution.
    amplitudes : numpy.ndarray, shape (N//2,)
        Amplitudes, the unit of ``signal``.
    """
    x = np.asarray(signal, float)
    spec = np.fft.rfft(x - x.mean())
    h = np.arange(1, spec.size)
    amp = 2 * np.abs(spec[1:]) / x.size
    return h * (2 * math.pi / full_period_output_rad), amp


def check_te_inputs(output_torque_Nm, samples, per_pitch) -> None:
    """The loaded TE's inputs in range, or the one-line refusal naming the key.

    Parameters
    ----------
    output_torque_Nm : float
        [N m], nonzero and finite.
    samples, per_pitch : int
        Sampled pitches and positions per pitch, 1 to 400.

    Raises
    ------
    CaseError
        For a value out of its range.
    """
    check_range("te_torque_Nm", output_torque_Nm, error=CaseError)
    if output_torque_Nm == 0:
        raise CaseError("te_torque_Nm = 0 is outside the valid range: nonzero")
    check_range("te_samples", samples, 1, 400, error=CaseError)
    check_range("te_positions", per_pitch, 1, 400, error=CaseError)


def loaded_record(drive, output_torque_Nm: float, te, mesh, pitches, per_pitch: int, *,
                  full_period: int | None = None):
    """The LoadedTE of a TE filled over the full period: its crank and output angles and its
    harmonics per output revolution.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    output_torque_Nm : float
        [N m].
    te, mesh : numpy.ndarray, shape (N,)
        The TE and the mesh's part of it over the full period's grid [rad].
    pitches : tuple of int
        The sampled pitches.
    per_pitch : int
        Positions per pitch.
    full_period : int, optional
        Pitches of the period the TE covers (default ``drive.full_period_pitches``; a built
        stage's may be longer).

    Returns
    -------
    LoadedTE
    """
    k = drive.full_period_pitches if full_period is None else int(full_period)
    crank = np.arange(np.size(te)) * (drive.period_rad / per_pitch)
    speeds = drive.speeds()
    out_per_crank = abs(speeds["output"] / speeds["crank"])
    orders, amp = harmonic_amplitudes(te, k * drive.period_rad * out_per_crank)
    return LoadedTE(output_torque_Nm=float(output_torque_Nm), crank_angle_rad=crank,
                    output_angle_rad=crank * out_per_crank, te_rad=te, mesh_rad=mesh,
                    sampled_pitches=pitches, per_pitch=int(per_pitch), full_period_pitches=k,
                    orders_per_output_rev=orders, amplitude_arcsec=amp / ARCSEC)


def coupled_matrix(drive, supports) -> np.ndarray:
    """The shared parts' compliance between the members, every part summed.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports

    Returns
    -------
    numpy.ndarray, shape (M, M)
        S [rad/(N m)]: member j turns by ``S[j] @ T`` under the member torques T.
    """
    m = drive.members
    return sum(drive.coupled_compliance(supports).values(), np.zeros((m, m)))


def even_coupling(coupling) -> bool:
    """Whether the shared parts load every member alike under the even split (equal row
    sums of S): with the members' own paths alike too, T/M each is then the split.

    Parameters
    ----------
    coupling : numpy.ndarray, shape (M, M)
        S [rad/(N m)].

    Returns
    -------
    bool
    """
    rows = np.asarray(coupling, float).sum(axis=1)
    return bool(np.allclose(rows, rows[0], rtol=1e-12, atol=0.0))


def even_by_layout(drive, supports, per_pitch: int) -> bool:
    """Whether the even split holds at every position by the drive's symmetry: every member
    at the first member's configuration and the shared parts loading each alike.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    per_pitch : int
        Positions per pitch of the grid the offsets are counted on.

    Returns
    -------
    bool
        True when T_j = T/M solves the split at every position (it is then the solution:
        each member's twist rises with its torque).
    """
    return (len(set(drive.member_offsets(per_pitch))) == 1
            and even_coupling(coupled_matrix(drive, supports)))


def even_split(drive, output_torque_Nm: float, per_pitch: int) -> MemberSplit:
    """The even split T/M of every member over the full period, as a layout's symmetry
    gives it (:func:`even_by_layout`), nothing solved.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    output_torque_Nm : float
        [N m].
    per_pitch : int
        Positions per pitch of the full-period grid.

    Returns
    -------
    MemberSplit
        ``even_by_layout`` True.
    """
    n = drive.full_period_pitches * int(per_pitch)
    share = np.full((drive.members, n), 1.0 / drive.members)
    return MemberSplit(share=share, crank_angle_rad=np.arange(n) * (drive.period_rad / per_pitch),
                       output_torque_Nm=float(output_torque_Nm),
                       offsets=drive.member_offsets(per_pitch), per_pitch=int(per_pitch),
                       even_by_layout=True)

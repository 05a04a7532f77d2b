"""Loaded transmission error over the drive's full period and the torque split between
its members (docs/stiffness.md).

The full period. A cycloid disc's contacts at pin pitch m are those of pitch 0 moved m
lobes on against the disc's holes, so the mesh repeats after Za / gcd(Za, s) pitches (s the
hole pattern's symmetry; ``Drive.full_period_pitches``), not after one. Resolving every
contact of that period in one mesh would refine the whole loaded flank (some 300k dofs for
the pin-housing drive), so the period is sampled: ``samples`` cycle solvers, each over one
pitch at pitches m_q spread over the period (one factorisation each, kept in the disk
cache), give the twist at every position of those pitches; a least-squares Fourier series
in m through the samples fills the other pitches (exact for the hole-induced variation up
to the order (samples - 1) / 2 per full period; the pin-pitch ripple comes from each
pitch's own positions).

The split. Each member (disc) is a load path from the output to the housing: its mesh,
its own bearings, and the crankshafts the members share; all turn the output by the same
twist. About the even split each path is linearised (its twist and its slope from the FE
at +-SPLIT_DELTA of the even share); the torques T_j with sum T that give one twist solve
a small linear system at every position of the full period. Member j sits at its own
place on the full-period grid (``Drive.member_offsets``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import CaseError, check_range
from .twist import ARCSEC, TwistModel

#: Relative torque step of the members' slopes (secant over +-5 % of the even share: the
#: Hertzian mesh stiffens by T^(1/3)-ish, so the secant differs from the tangent by ~0.1 %).
SPLIT_DELTA = 0.05
#: Default cycle solvers over the full period and positions per pitch of each.
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
    mesh_rad: np.ndarray             # (N,) the first member's mesh rotation
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
    """The output torque's split between the members over the full period."""
    share: np.ndarray                # (M, N) T_j / T
    crank_angle_rad: np.ndarray      # (N,)

    @property
    def load_factor(self) -> float:
        """Largest member torque over the even share (the seed's disc load factor)."""
        return float(np.max(self.share) * self.share.shape[0])

    def summary(self) -> dict:
        """The figures of the data sheet's member-split row.

        Returns
        -------
        dict
            Largest, smallest and mean share per member [-], and the load factor.
        """
        return {"member_share_max": float(np.max(self.share)),
                "member_share_min": float(np.min(self.share)),
                "member_share_mean": [float(x) for x in self.share.mean(axis=1)],
                "member_load_factor_fe": self.load_factor}


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


def loaded_te(drive, supports, output_torque_Nm: float, *, samples: int = DEFAULT_SAMPLES,
              per_pitch: int = DEFAULT_PER_PITCH, cache=True):
    """Loaded TE over the full period and, for several members, their split.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    supports : toothfem.fem.datasheet.supports.Supports
    output_torque_Nm : float
        Output torque [N m], either sign, nonzero.
    samples : int
        Cycle solvers over the full period (each one pitch).
    per_pitch : int
        Positions per pitch of each.
    cache
        The disk cache (as ``Drive.cycle_solver``).

    Returns
    -------
    (LoadedTE, MemberSplit or None)

    Raises
    ------
    CaseError
        If the torque is zero or not finite, or ``samples`` or ``per_pitch`` is outside
        [1, 400].
    """
    check_range("te_torque_Nm", output_torque_Nm, error=CaseError)
    if output_torque_Nm == 0:
        raise CaseError("te_torque_Nm = 0 is outside the valid range: nonzero")
    check_range("te_samples", samples, 1, 400, error=CaseError)
    check_range("te_positions", per_pitch, 1, 400, error=CaseError)
    k = drive.full_period_pitches
    pitches = sampled_pitches(k, samples)
    t = float(output_torque_Nm)
    opts = drive.both_sides_options if t < 0 else {}
    own, slope, shared, mesh = [], [], [], []
    for m in pitches:
        model = TwistModel(drive, supports, drive.cycle_solver(
            per_pitch, cache=cache, solver_options=opts, pitch=m))
        p = model.at(t)
        names = model.member_path_names
        own.append(sum(p.paths[n] for n in names))
        shared.append(p.total - own[-1])
        mesh.append(p.paths["mesh"])
        if drive.members > 1:
            hi, lo = model.at(t * (1 + SPLIT_DELTA)), model.at(t * (1 - SPLIT_DELTA))
            d_own = sum(hi.paths[n] - lo.paths[n] for n in names)
            slope.append(d_own / (2 * SPLIT_DELTA * model.member_torque(t)))
    fill = lambda v: fourier_fill(pitches, np.array(v), k).ravel()  # noqa: E731
    own_full, shared_full, mesh_full = fill(own), fill(shared), fill(mesh)
    n_all = own_full.size
    crank = np.arange(n_all) * (drive.period_rad / per_pitch)
    speeds = drive.speeds()
    out_per_crank = abs(speeds["output"] / speeds["crank"])
    split = None
    te = own_full + shared_full
    if drive.members > 1:
        split, te = _split(drive, supports, t, own_full, fill(slope), shared_full, per_pitch)
        split = MemberSplit(share=split, crank_angle_rad=crank)
    orders, amp = harmonic_amplitudes(te, k * drive.period_rad * out_per_crank)
    return LoadedTE(output_torque_Nm=t, crank_angle_rad=crank,
                    output_angle_rad=crank * out_per_crank, te_rad=te, mesh_rad=mesh_full,
                    sampled_pitches=pitches, per_pitch=int(per_pitch), full_period_pitches=k,
                    orders_per_output_rev=orders, amplitude_arcsec=amp / ARCSEC), split


def _split(drive, supports, t, own, slope, shared, per_pitch):
    """(shares (M, N), output twist (N,)): member j, at grid index g + offset_j, carries
    T/M + dT_j; its twist own_j + c_j dT_j + sum_i S_ji (T/M + dT_i) is the common theta
    and sum dT_j = 0 (own_j, c_j its own path's twist and slope at the even share, S the
    shared crankshafts); the parts every path runs through are added to theta."""
    m = drive.members
    n_all = own.size
    offsets = drive.member_offsets(per_pitch)
    idx = (np.arange(n_all)[None, :] + np.asarray(offsets)[:, None]) % n_all   # (M, N)
    s = sum(drive.coupled_compliance(supports).values(), np.zeros((m, m)))
    tm = math.copysign(drive.member_torque(abs(t), peak=False), t)
    shares = np.empty((m, n_all))
    common = np.empty(n_all)
    # the even-split twist of the shared parts (crank bending) is in ``shared`` already
    shared_even = s @ np.full(m, tm)
    for g in range(n_all):
        a = np.zeros((m + 1, m + 1))
        a[:m, :m] = np.diag(slope[idx[:, g]]) + s
        a[:m, m] = -1.0
        a[m, :m] = 1.0
        rhs = np.concatenate([-(own[idx[:, g]] + shared_even), [0.0]])
        x = np.linalg.solve(a, rhs)
        shares[:, g] = (tm + x[:m]) / t
        common[g] = x[m]
    # twist = own_j + c_j dT_j + S (T/M + dT) = x[m]; plus the parts every path runs through
    other = shared - shared_even[0]
    return shares, common + other


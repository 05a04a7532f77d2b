"""The thresholds of the measured-data loop: selection, held-out error and residual trends.

One record, shared by the fit (:mod:`.fit`: folds, seed, function evaluations), the residual
analysis (:mod:`.trends`: trend level, share, levels, degree) and the selection
(:mod:`.selection`: BIC and held-out gains, number of effects, aliasing) and the binning of
many rows (:mod:`.binning`).
"""
from __future__ import annotations

from dataclasses import dataclass

from ...errors import check_range


@dataclass(frozen=True, kw_only=True)
class Settings:
    """Thresholds of the selection and of the residual analysis (the reason beside each)."""
    folds: int = 5                 # k of the k-fold held-out error
    delta_bic: float = 10.0        # BIC decrease an effect must bring ('very strong',
                                   # Kass & Raftery 1995)
    min_cv_gain: float = 0.02      # and at least this relative cut of the held-out error
    max_effects: int = 4           # never more effects than this
    min_points: int = 8            # below: no selection (no held-out error to speak of)
    alpha_trend: float = 1e-3      # family-wise level of 'the residual follows x'
    r2_trend: float = 0.05         # and at least this share of the residual variance
    max_levels: int = 6            # a covariate with at most this many values: one mean each
    degree: int = 3                # polynomial degree of a covariate's smooth trend
    alias_bic: float = 6.0         # candidates within this BIC of the chosen one: aliased
                                   # (the data do not prefer the chosen one 'strongly',
                                   # Kass & Raftery 1995: 6)
    seed: int = 0                  # fold assignment
    max_nfev: int = 60             # function evaluations per least-squares fit
    max_points: int = 2000         # more rows than this are binned onto at most this many
                                   # operating points (binning.py): 12 cells on each of
                                   # speed, torque and oil temperature, 200x the most
                                   # parameters a selection fits (4 effects, ~8) and far
                                   # beyond the degree-3 residual trends; every row's
                                   # information kept (a bin's mean, sigma s/sqrt(n)). A
                                   # loop's time goes with the points times the model
                                   # evaluations: a million rows within the minute with
                                   # 17 candidates and pairs (issue 45; 5000 took twice)

    def __post_init__(self):
        check_range("folds", self.folds, 2, why="one fold to hold out and one to train on")
        check_range("min_points", self.min_points, 1)
        check_range("max_points", self.max_points, self.min_points,
                    why="at least min_points, or no selection is made")


#: The default thresholds, one instance shared as every function's default (Settings is
#: frozen and holds only numbers, so sharing it is safe).
DEFAULT_SETTINGS = Settings()

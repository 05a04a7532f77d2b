"""The tolerance ensemble's result (:class:`ToleranceResult`, ``toothfem tolerance``): the
outputs of a built reducer with their labels and units (:func:`output_labels`), the
percentiles of each output on its unfavourable side with distribution-free confidence
intervals (:func:`percentile_ci`, :func:`rings_needed`), the variance shares, and the check
of the nominal design and the percentiles against the case's limits (:func:`check_limits`,
through :mod:`toothfem.limits`). The ensemble itself: :mod:`toothfem.tolerance`;
docs/tolerance.md, "What a sample reports".
"""
from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from . import limits
from .quantities import PERCENTILES, side_of

#: Where the outputs come from (the labels say it: the nominal design's figures differ from
#: ``toothfem contact``'s, whose counts and forces are one disc held at its bearing seats
#: over one pitch, and from ``toothfem run``'s efficiency, whose loads are the analytic
#: split or that held disc's).
SYSTEM_WHERE = "system model, positions over the pairing period"


def output_labels(contact: str = "contact", contacts: str = "contacts", member: str = "disc",
                  members: int = 2) -> dict:
    """The outputs of a ring, column -> (label, unit), each label naming the model and the
    positions that gave it.

    Parameters
    ----------
    contact, contacts, member : str
        The drive's words for a contact, several, and the moving member ("pin", "pins",
        "disc"; "tooth", "teeth", "planet").
    members : int
        Moving members sharing the torque (one planet: no "any" or "first" of them).

    Returns
    -------
    dict
        {column: (label, unit)} in the order of the tables and pictures.
    """
    where, model = SYSTEM_WHERE, "system model"
    several = members > 1
    loads = (f"the system model's loads of the first {member}, every {member} taken alike"
             if several else f"the system model's loads of the {member}")
    on = f"any {member}" if several else f"the {member}"
    one = f"one {member}" if several else f"the {member}"
    return {
        "max_force_N": (f"largest {contact} force on {on} ({where})", "N"),
        "max_ph_MPa": (f"largest Hertz pressure P_h on {on} ({where})", "MPa"),
        "contacts_min": (f"fewest {contacts} in contact on {one} at a position "
                         f"({where})", "-"),
        "lost_motion_arcmin": (f"lost motion, elastic curve at +-3 % of the rated torque "
                               f"({model}, no friction)", "arcmin"),
        "backlash_arcmin": (f"backlash ({model}; < 0: the flanks interfere, preloaded; both "
                            "tails: P10 the interference side, P90 the play side)", "arcmin"),
        "te_mean_arcsec": (f"transmission error of the reducer at the operating torque, "
                           f"mean ({where})", "arcsec"),
        "te_pp_arcsec": (f"transmission error of the reducer, peak to peak ({where})",
                         "arcsec"),
        "mesh_efficiency_pct": (f"mesh efficiency ({loads})", "%"),
        "total_efficiency_pct": (f"total efficiency ({loads})", "%"),
    }


#: The outputs of a sample: column -> (label, unit) for tables and pictures (the system
#: model's words; :func:`output_labels` gives a drive's own).
OUTPUTS = output_labels()
#: Outputs that are counts: their percentiles are sample values (an order statistic on the
#: unfavourable side, COUNT_METHOD), never between two counts ("7.5 pins").
COUNTS = frozenset({"contacts_min"})
COUNT_METHOD = "lower"


#: Confidence of a percentile's interval (distribution-free, from the order statistics:
#: the ranks a binomial(n, q) count of samples below the q-quantile reaches at its
#: (1 - c)/2 and (1 + c)/2 quantiles). A percentile whose interval runs past the sample
#: (too few reducers for it: P99 needs 368) is not given; the summary says how many it needs.
CONFIDENCE = 0.95
#: Most samples one run takes (1e5 rings x 36 positions: about an hour on 2 cores).
MAX_SAMPLES = 100_000
#: The sizes :func:`rings_needed` searches up to, block by block (the first that answers
#: is the same as over 1 to MAX_SAMPLES at once, found without the larger blocks).
RINGS_SEARCH_BLOCKS = (512, 8192)


@dataclass(frozen=True, kw_only=True)
class ToleranceResult:
    """The ensemble: ``samples`` {output: (N,)}, the ``nominal`` design's outputs on the
    same positions, ``shares`` {tolerance: {output: share of the variance}} from the runs
    with one tolerance at a time (and ALONE_OVER_ALL: their variances summed over the
    whole ensemble's), ``settings`` (samples, seed, positions, tolerances in mm);
    ``film_ratio`` {contacts: {"nominal": lowest or None, "samples": (N,)}}: the efficiency
    model's lowest film ratio where it is below FILM_RATIO_BOUNDARY (inf in ``samples``,
    None for the nominal: not below it); ``limits`` the limits the outputs are drawn
    against ({output: [{name, value, unit, source}]}); ``warnings`` the limits passed
    (:class:`toothfem.limits.Exceeded`, :func:`check_limits`)."""
    case_name: str
    drive: str
    contact_name: str
    contacts_name: str
    samples: dict
    nominal: dict
    shares: dict
    settings: dict
    member_name: str = "disc"
    members: int = 2
    film_ratio: dict = dataclasses.field(default_factory=dict)
    limits: dict = dataclasses.field(default_factory=dict)
    warnings: tuple = ()
    maker: dict = dataclasses.field(default_factory=dict)   # [published] {output: value}

    def table(self) -> list:
        """The ensemble's rows: each output's nominal value and percentiles, in the drive's
        words.

        Returns
        -------
        list of (quantity, unit, {column: value})
            (:func:`toothfem.report.tolerance.summary_rows`).
        """
        from .report.tolerance import summary_rows
        return summary_rows(self.summary(), self.outputs())

    def plot(self) -> dict:
        """The ensemble's pictures.

        Returns
        -------
        dict
            File name -> matplotlib Figure (:func:`toothfem.report.tolerance.
            tolerance_figures`).
        """
        from .report.tolerance import tolerance_figures
        return tolerance_figures(self)

    def write(self, folder) -> dict:
        """samples.csv, summary.json, the pictures and report.md into an existing
        ``folder``.

        Parameters
        ----------
        folder : path

        Returns
        -------
        dict
            The summary with the files written (:func:`toothfem.report.tolerance.
            write_tolerance`).
        """
        from .report.tolerance import write_tolerance
        return write_tolerance(self, folder)

    def percentiles(self) -> dict:
        """The ensemble's percentiles of each output on its unfavourable side
        (PERCENTILES, LOW_IS_WORSE; both tails of TWO_SIDED), each with its CONFIDENCE
        interval.

        Returns
        -------
        dict
            {output: {"P50": {"value", "ci", "rings_needed"}, "P90" or "P10": ..,
            "P99" or "P1": ..}} in the output's unit (OUTPUTS): ``value`` and ``ci``
            ([low, high]) None where the sample is too small for the percentile, which
            then needs ``rings_needed`` reducers.
        """
        return {k: {f"P{q}": percentile_ci(v, q / 100, method=COUNT_METHOD if k in COUNTS
                                           else "linear")
                    for q in PERCENTILES[side_of(k)]}
                for k, v in self.samples.items()}

    def outputs(self) -> dict:
        """The outputs in the drive's own words, each label naming its model and positions
        (:func:`output_labels`).

        Returns
        -------
        dict
            {column: (label, unit)}.
        """
        return output_labels(self.contact_name, self.contacts_name, self.member_name,
                             self.members)

    def film_ratio_percentiles(self) -> dict:
        """The lowest film ratio's low-side percentiles over the ensemble (P50, P10, P1)
        that the sample is large enough for (``rings_needed``, as the outputs'), each
        ``value`` None where it is not below FILM_RATIO_BOUNDARY.

        Returns
        -------
        dict
            {contacts: {"P50": {"value", "rings_needed"}, ...}}.
        """
        out: dict[str, dict] = {}
        for where, rec in self.film_ratio.items():
            x = np.asarray(rec["samples"], float)
            if x.size == 0 or np.any(np.isnan(x)):        # rings of an older run: not known
                continue
            out[where] = {}
            for q in PERCENTILES["low"]:
                needed = rings_needed(q / 100)
                if x.size < needed:
                    continue
                # a ring not below the limit stands in as a huge value: a percentile that
                # reaches one is not below the limit either
                v = float(np.percentile(np.where(np.isfinite(x), x, _NOT_BELOW), q))
                out[where][f"P{q}"] = {"value": v if v < limits.FILM_RATIO_BOUNDARY
                                       else None, "rings_needed": needed}
        return out

    def summary(self) -> dict:
        """The result as summary.json holds it.

        Returns
        -------
        dict
            Case, drive, the settings, the outputs' labels, the nominal outputs,
            percentiles, means, the variance shares, the film ratio, the limits and the
            ``warnings`` (the limits passed, :meth:`toothfem.limits.Exceeded.as_dict`).
        """
        return {"case": self.case_name, "drive": self.drive, "member": self.member_name,
                "members": self.members, **self.settings,
                "outputs": {k: list(v) for k, v in self.outputs().items()},
                "nominal": self.nominal, "percentiles": self.percentiles(),
                "maker": self.maker,
                "mean": {k: float(np.mean(v)) for k, v in self.samples.items()},
                "variance_shares": self.shares,
                "film_ratio_lowest": {
                    where: {"nominal": rec["nominal"], **{
                        q: p["value"] for q, p in
                        self.film_ratio_percentiles().get(where, {}).items()}}
                    for where, rec in self.film_ratio.items()},
                "limits": self.limits,
                "warnings": [w.as_dict() for w in self.warnings]}


#: What a ring whose film ratio is not below the limit stands in as for the percentiles.
_NOT_BELOW = 1e300


def percentile_ci(values, q: float, confidence: float = CONFIDENCE,
                  method: str = "linear") -> dict:
    """A percentile of a sample with its distribution-free confidence interval.

    The interval is [x_(l), x_(u)] of the sorted sample (1-based ranks), l and u - 1 the
    binomial(n, q) count's (1 - c)/2 and (1 + c)/2 quantiles: it holds the true
    q-quantile with probability at least about c whatever the distribution.

    Parameters
    ----------
    values : array_like
        The sample, (n,).
    q : float
        The quantile, in (0, 1).
    confidence : float
        c, in (0, 1).
    method : str
        numpy's percentile method: "linear" interpolates, "lower" takes the sample value
        at or below (a count's, on its low side).

    Returns
    -------
    dict
        ``value`` (numpy's percentile by ``method``) and ``ci`` ([low, high]), both None
        when the interval's ranks pass the sample's ends; ``rings_needed``: the fewest
        samples whose interval stays inside.
    """
    from scipy.stats import binom

    x = np.sort(np.asarray(values, float))
    n = x.size
    needed = rings_needed(q, confidence)
    if n < needed:
        return {"value": None, "ci": None, "rings_needed": needed}
    lo = int(binom.ppf((1 - confidence) / 2, n, q))
    hi = int(binom.ppf((1 + confidence) / 2, n, q)) + 1
    return {"value": float(np.percentile(x, 100 * q, method=method)),  # type: ignore[call-overload]  # method: a str of numpy's Literal
            "ci": [float(x[lo - 1]), float(x[hi - 1])], "rings_needed": needed}


@functools.cache
def rings_needed(q: float, confidence: float = CONFIDENCE) -> int:
    """The fewest samples whose :func:`percentile_ci` interval of the q-quantile lies
    inside the sample (rank 1 to n): 6 for the median, 36 for P90 or P10, 368 for P99 or
    P1 at 95 %.

    Parameters
    ----------
    q, confidence : float
        As :func:`percentile_ci`.

    Returns
    -------
    int
    """
    from scipy.stats import binom

    start = 1
    for end in (*RINGS_SEARCH_BLOCKS, MAX_SAMPLES):     # the first n, block by block: the
        if end < start:                                 # binomial's ppf over all 1e5
            continue                                    # sizes took a second a call
        n = np.arange(start, end + 1)
        ok = ((binom.ppf((1 - confidence) / 2, n, q) >= 1)
              & (binom.ppf((1 + confidence) / 2, n, q) + 1 <= n))
        if ok.any():
            return int(n[np.argmax(ok)])
        start = end + 1
    return MAX_SAMPLES + 1


def check_limits(result: ToleranceResult, si) -> tuple:
    """The ensemble against the case's limits (:mod:`toothfem.limits`, each check done
    there): the largest Hertz pressure of the nominal design and of each percentile given
    (:func:`toothfem.limits.contact_pressure`), the lowest film ratio likewise
    (:func:`toothfem.limits.film_ratio`, low side), and the operating output torque
    against the rating (:func:`toothfem.limits.rated_torque`).

    Parameters
    ----------
    result : ToleranceResult
        Its nominal, samples and film ratios.
    si : toothfem.si.CaseSI
        The case: its material and operating limits.

    Returns
    -------
    found : list of toothfem.limits.Exceeded
        Each limit passed, its quantity naming the contacts, the model and which figure
        (the nominal design, or "P90 of 200 built reducers" with its 95 % interval).
    drawn : dict
        {output: [{"name", "value", "unit", "source"}]}: the limits to mark on the
        outputs' pictures (the allowable and static contact stress on the pressure's).
    """
    n = next((v.size for v in result.samples.values()), 0)
    where = f"the {result.contact_name} contacts in the reducer (system model)"

    def at(q, p=None, unit=""):
        if q is None:
            return "the nominal design"
        ci = "" if p is None or p.get("ci") is None else \
            f" (95 % interval {p['ci'][0]:.4g} to {p['ci'][1]:.4g} {unit})"
        return f"{q} of {n} built reducers{ci}"

    found = list(limits.rated_torque(si, result.settings.get(
        "operating_output_torque_Nm", 0.0)))
    found += limits.contact_pressure(f"{where}, {at(None)}", result.nominal["max_ph_MPa"],
                                     si.material)
    for q, p in result.percentiles().get("max_ph_MPa", {}).items():
        if p["value"] is not None:
            found += limits.contact_pressure(f"{where}, {at(q, p, 'MPa')}", p["value"],
                                             si.material)
    pct = result.film_ratio_percentiles()
    for contacts, rec in result.film_ratio.items():
        if rec["nominal"] is not None:
            found += limits.film_ratio(f"{contacts}, {at(None)}", rec["nominal"])
        for q, p in pct.get(contacts, {}).items():
            if p["value"] is not None:
                found += limits.film_ratio(f"{contacts}, {at(q)}", p["value"])
    return found, {"max_ph_MPa": limits.contact_pressure_lines(si.material)}



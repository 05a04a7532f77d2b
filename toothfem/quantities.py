"""The quantities the outputs name, once: each summary key (its name and unit suffix, the
key of summary.json) with what a reader sees (label, unit) and its one definition.

A key's unit comes from its suffix (:func:`toothfem.units.unit_of`, the one unit table);
the label is the row of every table, the terminal's and report.md's and report.html's
alike. ``{contact}``, ``{contacts}`` and ``{member}`` in a name or label are the drive's
words (pin/pins/disc, tooth/teeth/planet). A variant of a quantity (one member held
against the reducer, a pitch against the full period) is its own key with its own label
saying which it is.
"""
from __future__ import annotations

from dataclasses import dataclass

from .units import unit_of


@dataclass(frozen=True)
class Quantity:
    """One output quantity (module docstring): its ``key`` (with the unit suffix, the
    summaries' key), the ``label`` a table shows, its ``definition``, and a ``unit`` that
    overrides the key's suffix where the key has none (counts, ratios) or says more."""
    key: str
    label: str
    definition: str = ""
    unit: str | None = None

    def unit_symbol(self, words: dict | None = None) -> str:
        """The unit a table shows: ``unit`` where given, else the key's suffix's symbol.

        Parameters
        ----------
        words : dict, optional
            The drive's words, for a key that names them.

        Returns
        -------
        str
        """
        if self.unit is not None:
            return self.unit
        u = unit_of(self.key_for(words or {}))
        return "" if u is None else u.symbol

    def key_for(self, words: dict) -> str:
        """The summary key with the drive's words.

        Parameters
        ----------
        words : dict
            ``contact``, ``contacts``, ``member``.

        Returns
        -------
        str
        """
        return self.key.format(**words)

    def label_for(self, words: dict) -> str:
        """The label with the drive's words.

        Parameters
        ----------
        words : dict
            ``contact``, ``contacts``, ``member``.

        Returns
        -------
        str
        """
        return self.label.format(**words)


#: The contact summary's quantities (``toothfem contact``, the run's contact table), in
#: the order of the table.
CONTACT = (
    Quantity("{contacts}_in_contact_max", "{contacts} in contact, most", unit=""),
    Quantity("{contacts}_in_contact_min", "{contacts} in contact, fewest", unit=""),
    Quantity("max_force_reducer_N", "largest {contact} force in the reducer (system model: "
             "every {member} free on its supports)"),
    Quantity("max_ph_reducer_MPa", "largest Hertz pressure P_h in the reducer (system model)"),
    Quantity("max_force_N", "largest {contact} force, one {member} held at its bearing seats "
             "(member torque)"),
    Quantity("max_ph_MPa", "largest Hertz pressure P_h, one {member} held at its bearing "
             "seats"),
    Quantity("face_slices", "  slices along the face width (P_h: the peak along it)", unit=""),
    Quantity("max_ph_centre_MPa", "  largest P_h at the middle of the face"),
    Quantity("max_ph_edge_MPa", "  largest P_h at the edges of the face (the end slices)"),
    Quantity("edge_to_centre_ph", "  edge to middle, largest P_h", unit=""),
    Quantity("peak_ph_z_mm", "  where the largest P_h sits along the width (0: the middle)"),
    Quantity("tilt_moment_max_Nm", "  the {contacts}' moment on one {member} about its tilt axis, "
             "largest"),
    Quantity("output_pin_force_max_N", "largest output pin force on a hole (system model, one pitch)",
             "the output flange's pins on the members' holes, every member free on its "
             "supports (toothfem.output_pins.DEFINITION)"),
    Quantity("output_pin_ph_max_MPa", "largest Hertz pressure P_h, output pin (roller) on "
             "its hole, one pitch", "the pin, or its roller where it has one, in the hole: Hertz's "
             "line contact over the member's face width"),
    Quantity("output_pins_in_contact_min", "output pins carrying on one {member}, fewest",
             unit=""),
    Quantity("transmission_error_reducer_arcsec", "transmission error of the reducer (system "
             "model) at the output torque, mean"),
    Quantity("transmission_error_reducer_ripple_arcsec", "  its peak to peak over one pitch at "
             "the run's positions (the full period: toothfem stiffness)"),
    Quantity("transmission_error_reducer_mesh_arcsec", "  of it the mesh ({contact} contacts), "
             "mean"),
    Quantity("transmission_error_arcsec", "mesh rotation of one {member} held at its bearing "
             "seats, mean"),
    Quantity("transmission_error_ripple_arcsec", "  its peak to peak"),
    Quantity("worst_position_deg", "worst position (largest force)", unit="deg crank"),
    Quantity("hertz_invalid_contacts", "contacts where Hertz fails (b not << R)", unit=""),
    Quantity("ph_from_fe_contacts", "of them with P_h from the FE", unit=""),
    Quantity("torque_equilibrium_max_rel_error", "torque equilibrium error", unit="relative"),
    Quantity("backlash_min_arcmin", "backlash before load (both flanks, input held), least"),
    Quantity("disc_backlash_min_arcmin", "  the disc's own free turn, its cranks held, least"),
    Quantity("clearance_before_load_um", "clearance before load, least (< 0: interference)",
             unit="um"),
    Quantity("interference_before_load_um", "interference before load, largest", unit="um"),
    Quantity("interference_pins", "{contacts} interfering (+: flank of a positive torque)",
             unit=""),
    Quantity("preload_force_max_N", "  largest {contact} force before load (preload)"),
    Quantity("preload_ph_max_MPa", "  its Hertz pressure P_h"),
)

#: The datasheet's quantities (``toothfem stiffness``, the run's datasheet table).
DATASHEET = {q.key: q for q in (
    Quantity("rated_torque_Nm", "rated torque"),
    Quantity("torsional_rigidity_Nm_per_arcmin", "torsional rigidity 50-100 %",
             "the secant slope of the elastic twist between half and all of the rated "
             "torque, both directions' mean (the catalogue's b/a)"),
    Quantity("lost_motion_arcmin", "lost motion ±3 %",
             "the twist between +3 % and -3 % of the rated torque on the loop's mean curve"),
    Quantity("backlash_arcmin", "backlash",
             "the twist between the two flanks' first contact at zero torque"),
    Quantity("hysteresis_loss_arcmin", "hysteresis loss",
             "the loop's width at zero torque"),
    Quantity("te_mean_arcsec", "transmission error of the reducer at {torque} N m, mean",
             "the output's lag behind its kinematic position, input held (system model)"),
    Quantity("te_peak_to_peak_arcsec", "  its peak to peak over the full period ({period})"),
)}


#: The accuracy life's quantities (``toothfem wear``: each row of its history).
WEAR = {q.key: q for q in (
    Quantity("hours", "running time of the duty cycle", unit="h"),
    Quantity("lost_motion_arcmin", "lost motion ±3 %", "as the datasheet's, with the "
             "clearances worn by then"),
    Quantity("backlash_arcmin", "backlash", "as the datasheet's, worn"),
    Quantity("te_mean_arcsec", "transmission error at the rated torque, mean",
             "the system model's over one pin pitch, worn"),
    Quantity("te_peak_to_peak_arcsec", "  its peak to peak over one pitch"),
    Quantity("efficiency", "efficiency at the duty cycle's first row", unit="",
             definition="the efficiency model's losses with the pins' contact loss of the "
                        "worn reducer's loads and run-in roughness"),
)}

# -- the tolerance ensemble's outputs: which side of each is worse -------------------------

#: Outputs where low is worse (the rest: high is worse); their tail percentiles are taken
#: on that side: P10/P1 of the fewest contacts and the efficiencies, P90/P99 of forces,
#: pressures, lost motion and TE.
LOW_IS_WORSE = frozenset({"contacts_min", "mesh_efficiency_pct", "total_efficiency_pct"})

#: Outputs bad on both sides, with both tails given: the backlash (above: play, lost
#: motion at the output; below zero: the flanks interfere, the stage is preloaded, its
#: friction and heat rise and it may not assemble). One tail alone would hide the other.
TWO_SIDED = frozenset({"backlash_arcmin"})

#: Percentiles of each output, the median and the unfavourable tail (1 in 10 and 1 in
#: 100 of the built reducers worse than it), by the side that is worse; both sides for
#: TWO_SIDED.
PERCENTILES = {"high": (50, 90, 99), "low": (50, 10, 1), "both": (50, 10, 90, 1, 99)}

def side_of(output: str) -> str:
    """Which side of an output is worse: "high", "low" or "both" (PERCENTILES' keys).

    Parameters
    ----------
    output : str
        A column of OUTPUTS.

    Returns
    -------
    str
    """
    return "both" if output in TWO_SIDED else "low" if output in LOW_IS_WORSE else "high"

#: Key of the shares' last row: the one-tolerance variances summed, over the whole
#: ensemble's (1: the tolerances add up; above 1 they mask each other, as when one
#: tolerance's interference already decides which pins carry; below 1 they compound).
ALONE_OVER_ALL = "sum_alone_over_all"

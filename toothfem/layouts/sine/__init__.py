"""The one-tooth-difference sine reducer: the sine planet on the input's eccentric in its
ring, the torque out through pins in the planet's holes (Lu & Xu 2024)."""
from __future__ import annotations

from ...cad_parts import sine_parts
from ...efficiency.bearings import output_pin_force, pin_held_loads
from ...efficiency.drive_losses import LossModel
from ...layout import Layout
from ..common import NITRILE_SEAL_LIMIT_C, NITRILE_SEAL_SOURCE, needs_output_pins
from . import parts, template

LAYOUT = Layout(
    name="sine", module=__name__,
    label="a one-tooth-difference sine-profile reducer with output pins",
    stage_section="sine", tolerance_keys=("tooth_profile_mm",),
    required_sections={"sine": ("sine", "material")},
    components=frozenset({"teeth", "eccentric_bearing", "output_mechanism"}),
    # no maker's surface limit found for a K-H-V or sine reducer: the nitrile lip seals'
    # working range, the lumped heat balance's one temperature at the lips (ASSUMPTION)
    case_temperature_limit_C=NITRILE_SEAL_LIMIT_C, case_temperature_source=NITRILE_SEAL_SOURCE,
    drive=parts.sine_drive, ratio=parts.ratio, case_checks=needs_output_pins,
    case_template=template.SINE_TEMPLATE, derived_rows=parts.rows,
    loss_model=LossModel(
        parts.losses, bearing_coefficient_component="eccentric_bearing",
        sources={"eccentric_bearing": "f r_p F_R1 w_rel, F_R1 from the planet's equilibrium "
                                      "(Lu & Xu 2024, Eqs. 26-32)"}),
    envelope=parts.envelope, bearing_set=parts.bearings, eccentric_loads=pin_held_loads,
    main_row_force=output_pin_force, drawing=parts.pair_drawing, cad_parts=sine_parts)

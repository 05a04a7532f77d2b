"""The K-H-V cycloid drive: one input shaft with an eccentric per disc, the discs on their
pins, the torque out through pins (or rollers) in holes through the discs."""
from __future__ import annotations

from ...cad_parts import cycloid_parts
from ...efficiency.bearings import output_pin_force, pin_held_loads
from ...efficiency.drive_losses import LossModel
from ...layout import Layout
from ..common import NITRILE_SEAL_LIMIT_C, NITRILE_SEAL_SOURCE
from ..cycloid import CYCLOID_DESIGN, CYCLOID_TOLERANCES, cycloid_rows, pair_drawing
from . import parts, template

LAYOUT = Layout(
    name="cycloid", module=__name__,
    label="a K-H-V cycloid drive with output pins through the discs",
    stage_section="cycloid", tolerance_keys=CYCLOID_TOLERANCES, design_keys=CYCLOID_DESIGN,
    required_sections={"cycloid": ("cycloid", "material")},
    components=frozenset({"pins", "eccentric_bearing", "output_mechanism", "main_bearings"}),
    # no maker's surface limit found for a K-H-V or sine reducer: the nitrile lip seals'
    # working range, the lumped heat balance's one temperature at the lips (ASSUMPTION)
    case_temperature_limit_C=NITRILE_SEAL_LIMIT_C, case_temperature_source=NITRILE_SEAL_SOURCE,
    drive=parts.khv_drive, ratio=parts.ratio, case_checks=parts.case_checks,
    case_template=template.KHV_TEMPLATE, derived_rows=cycloid_rows,
    loss_model=LossModel(parts.losses), envelope=parts.envelope, bearing_set=parts.bearings,
    eccentric_loads=pin_held_loads, main_row_force=output_pin_force, drawing=pair_drawing,
    cad_parts=cycloid_parts)

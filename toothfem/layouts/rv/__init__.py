"""The RV (2K-V) reducer: a spur first stage turns crankshafts on the carrier, each through
a crank hole of every cycloid disc; the carrier is the output."""
from __future__ import annotations

from ...cad_parts import cycloid_parts
from ...efficiency.bearings import carrier_force, crank_held_loads
from ...efficiency.drive_losses import LossModel
from ...layout import Layout
from ..cycloid import CYCLOID_DESIGN, CYCLOID_TOLERANCES, pair_drawing
from . import parts, template

LAYOUT = Layout(
    name="rv", module=__name__,
    label="an RV (2K-V) reducer: a spur first stage, crankshafts, cycloid discs",
    stage_section="cycloid", tolerance_keys=CYCLOID_TOLERANCES, design_keys=CYCLOID_DESIGN,
    required_sections={"rv": ("rv",), "cycloid": ("cycloid", "material")},
    selected_by={"cycloid": "first_stage"},
    components=frozenset({"pins", "first_stage", "crank_bearings", "main_bearings"}),
    # Nabtesco's RV-E series catalogue (operating conditions: the reducer's surface at
    # most 60 C); an ASSUMPTION for a reducer of another maker
    case_temperature_limit_C=60.0,
    case_temperature_source="Nabtesco RV-E catalogue: the reducer's surface at most 60 C; "
                            "ASSUMPTION for this case (thermal.case_temperature_limit_C sets "
                            "it)",
    drive=parts.rv_drive, ratio=parts.ratio, case_checks=parts.case_checks,
    case_template=template.RV_TEMPLATE, derived_rows=parts.rows,
    loss_model=LossModel(parts.losses), envelope=parts.envelope, bearing_set=parts.bearings,
    eccentric_loads=crank_held_loads, main_row_force=carrier_force, drawing=pair_drawing,
    cad_parts=cycloid_parts)

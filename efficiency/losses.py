"""Every loss component, once: its name (the key of ``DriveLosses.losses_W``), the part of
the reducer it belongs to, and its law with its source (docs/efficiency.md).

The load-dependent components are computed by each layout's power flow from the mesh's
loads (``Layout.loss_model``); the load-independent ones are classes of
:mod:`toothfem.efficiency.no_load` (a new one: a :class:`~toothfem.efficiency.no_load.
NoLoadLoss` there, listed in ``NO_LOAD`` and here). The report's "each loss and its law",
the loop's effects that scale a loss (``Effect.linear_in`` names one of these) and
tests/test_losses.py read this table.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Loss:
    """One loss component (module docstring). ``part``: the part of the reducer it acts on,
    a ``Layout.components`` name ("pins", "eccentric_bearing" ...), or None where every
    layout has it (seals, drag)."""
    name: str
    part: str | None
    law: str


#: Every loss component of every layout, by name.
LOSSES: dict[str, Loss] = {x.name: x for x in (
    Loss("mesh", "teeth",
         "sliding friction of every loaded contact over the meshing period: EHL (Xu 2007) "
         "and asperity (boundary coefficient) shares of mixed lubrication"),
    Loss("pin_contacts", "pins",
         "pin-disc contacts: EHL (Xu 2007) and asperity shares of mixed lubrication, the "
         "pin turning in its groove where that slides more easily; the 2K-V train by Chen & "
         "Angeles' virtual power"),
    Loss("first_stage", "first_stage",
         "spur stage: Ohlendorf's loss factor with Schlenk's mean friction (ISO/TR 14179-2), "
         "or the declared mesh efficiency"),
    Loss("crank_bearings", "crank_bearings",
         "Palmgren M0 + mu P d_m/2 of each needle bearing at its load (Harris & Kotzalas "
         "2007)"),
    Loss("crank_support_bearings", "crank_bearings",
         "Palmgren M0 + mu P d_m/2 of each tapered roller bearing, load sum T/R_c (Harris & "
         "Kotzalas 2007)"),
    Loss("main_bearings", "main_bearings",
         "Palmgren M0 + mu P d_m/2 of the angular contact rows at their preload and the "
         "external loads (Harris & Kotzalas 2007)"),
    Loss("input_bearings", None,
         "Palmgren M0 + mu P d_m/2 of the input shaft's ball bearings (Harris & Kotzalas "
         "2007)"),
    Loss("eccentric_bearing", "eccentric_bearing",
         "Palmgren M0 + mu P d_m/2 of the eccentric's rollers at the member's equilibrium "
         "load (Harris & Kotzalas 2007)"),
    Loss("output_mechanism", "output_mechanism",
         "pins sliding in the member's holes, mu sum Q 2 a0 w (Lu & Xu 2024, Eqs. 37-39)"),
    Loss("plain_bearings", "output_mechanism",
         "the output pins' plain bearings, M_f w (Lu & Xu 2024, Eq. 34)"),
    Loss("churning", None,
         "oil-bath no-load loss, Lu & Xu 2024 Eq. 42 (after Xu & Yang 1998): validated by "
         "its source on the sine stage only"),
    Loss("bearing_drag", None,
         "Palmgren's viscous moment M0 of every bearing (f0 by type and lubrication, Harris "
         "& Kotzalas 2007)"),
    Loss("seals", None, "radial lip seals, ISO/TR 14179-1: 7.69e-6 D^2 n W"),
    Loss("drag", None, "declared drag torque on the input (friction.drag_torque_Nmm)"),
    Loss("windage", None,
         "declared drag on the input growing with speed squared, T_w (n/1000 rpm)^2 "
         "(friction.windage_torque_Nmm; Dawson 1984)"),
    Loss("viscous_drag", None,
         "declared drag on the input growing with speed and viscosity, T_v (n/1000 rpm) "
         "eta/eta_ref (friction.viscous_drag_Nmm; Petroff 1883)"),
    Loss("sun_planet_mesh", "first_stage",
         "RV paper Eqs. 8-15 with the declared mesh efficiency"),
    Loss("cycloid_mesh", "pins", "RV paper Eqs. 8-15 with the declared mesh efficiency"),
)}

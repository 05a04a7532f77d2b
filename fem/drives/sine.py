"""The sine-profile planet in its fixed ring (one-tooth-difference K-H-V pair)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ...geometry import sine as sg
from ...geometry.vectors import rotate
from .. import deviations as dv
from .. import sine_fe as sf
from ..datasheet import supports as sp
from .assembly import CycloidSystem
from ..system.paths import PinsInHoles
from ..system.mesh import ToothMesh
from .base import Drive, _merged_orders
from ...si import MaterialSI, OutputMechanismSI, SineStageSI

if TYPE_CHECKING:
    from ...layout import Layout
    from ..system.paths import OutputPath

#: Eccentric bearing's inner raceway when the case has no [output_mechanism]: a quarter of
#: the planet's pitch radius (ASSUMPTION; the prototype's 10 mm is 0.28 of its 35.55 mm).
ECCENTRIC_RACEWAY_REL = 0.25

#: Teeth of the sine pair within this unloaded gap share the load in the analytic split:
#: the order of the pair's elastic approach at the rig torque (Hertz approach of a few
#: micrometres plus tooth bending); the FE model finds the set itself.
SINE_IN_MESH_GAP_M = 5e-6


@dataclass(frozen=True, kw_only=True)
class SineDrive(Drive):
    """The sine pair in SI (:class:`toothfem.si.SineStageSI`) on its K-H-V output ``path``
    (:class:`toothfem.fem.system.paths.PinsInHoles`: the planet on the input's eccentric,
    its torque out through the output pins in its holes); the output mechanism (pins in
    holes) sets where the FE model holds the planet."""
    stage: SineStageSI
    material_si: MaterialSI
    layout: Layout = field(compare=False, repr=False)
    path: OutputPath = PinsInHoles()

    kind = "sine"
    member_name = "planet"
    contact_name = "tooth"
    contacts_name = "teeth"
    analytic_weight = "cos_pressure_angle"

    @classmethod
    def from_case(cls, si, layout: Layout) -> SineDrive:
        """The sine pair of a case, with its output mechanism if it has one.

        Parameters
        ----------
        si : toothfem.si.CaseSI
        layout : toothfem.layout.Layout

        Returns
        -------
        SineDrive

        Raises
        ------
        CaseError
            If the [sine] or the [material] section is missing.
        """
        if si.sine is None:
            raise CaseError("a [sine] section is required for drive = 'sine'")
        if si.material is None:
            raise CaseError("a [material] section is required for the contact analyses")
        return cls(stage=si.sine, material_si=si.material, layout=layout,
                   path=PinsInHoles(si.output_mechanism))

    @property
    def output_mechanism(self) -> OutputMechanismSI | None:
        """The output mechanism (pins in the planet's holes), the path's."""
        return self.path.output_mechanism

    @property
    def output(self):
        """The output mechanism (pins in the planet's holes): the path of the torque."""
        return self.output_mechanism

    @property
    def pair(self) -> sg.SineGearPair:
        return self.stage.pair

    @property
    def period_rad(self) -> float:
        return self.pair.crank_pitch_rad

    @property
    def members(self) -> int:
        return 1

    @property
    def load_factor(self) -> float:
        return 1.0

    @property
    def face_width_m(self) -> float:
        return self.pair.face_width_m

    @property
    def analytic_in_mesh_gap_m(self) -> float:
        return SINE_IN_MESH_GAP_M

    def speeds(self) -> dict:
        """K-H-V speeds of the pair, the path's
        (:func:`~toothfem.geometry.train.khv_speeds`).

        Returns
        -------
        dict of str to float
            The crank turns with the input; member and output are the planet.
        """
        return self.path.speeds(self.pair.planet_teeth, self.pair.ring_teeth)

    def te_orders(self) -> dict:
        """Orders per output revolution at which a TE ripple is expected, in the sine
        pair's terms (:meth:`Drive.te_orders`; from :meth:`speeds`, the ring fixed):

        - ``output revolution`` (1);
        - ``input revolution`` = ``crank revolution`` = ``planet-tooth passing (Z1)``: each
          ring tooth meets the loaded zone once per crank turn and sees the Z1 planet teeth
          go by in an output turn (the ring's tooth errors);
        - ``ring-tooth passing (Z2)``: each planet tooth meets the loaded zone once per turn
          of the crank against the planet, meeting the Z2 ring teeth in an output turn (the
          planet's tooth errors);
        - ``tooth mesh``: the meshing period, one per ring tooth pitch of crank.

        Returns
        -------
        dict of str to float
            name -> order [per output revolution]; equal orders share one entry, their
            names joined by " = ".
        """
        w = self.speeds()
        out = abs(w["output"])
        crank = abs(w["crank"]) / out
        return _merged_orders([
            ("output revolution", 1.0), ("input revolution", abs(w["input"]) / out),
            ("crank revolution", crank), ("planet-tooth passing (Z1)", crank),
            ("ring-tooth passing (Z2)", abs(w["crank"] - w["member"]) / out),
            ("tooth mesh", 2 * np.pi / self.period_rad * crank)] + self.path.te_orders(w))

    def meshing(self, positions_rad, crank_speed_rad_s: float = 1.0):
        """:func:`toothfem.geometry.sine.meshing` of the pair.

        Parameters
        ----------
        positions_rad : array_like, shape (P,)
            [rad] of crank.
        crank_speed_rad_s : float
            [rad/s].

        Returns
        -------
        toothfem.geometry.kinematics.MeshingState
        """
        return sg.meshing(self.pair, positions_rad, crank_speed_rad_s)

    def fe_model(self, **overrides):
        """:func:`toothfem.fem.sine_fe.model_from_pair` of the pair and its material.

        Parameters
        ----------
        **overrides
            Its keywords (supports, plane, candidates).

        Returns
        -------
        toothfem.fem.sine_fe.SineFEModel
        """
        return sf.model_from_pair(self.pair, self.material_si, self.output_mechanism,
                                  **overrides)

    def _new_cycle_solver(self, model, positions_rad, cache, **options):
        return sf.CycleSolver(model, positions_rad, cache=cache, **options)

    def solve_detailed(self, model, position_rad: float, member_torque_Nm: float):
        """:func:`toothfem.fem.sine_fe.solve_detailed` with its default zones.

        Parameters
        ----------
        model : toothfem.fem.sine_fe.SineFEModel
        position_rad : float
            [rad] of crank.
        member_torque_Nm : float
            Planet torque [N m].

        Returns
        -------
        toothfem.fem.sine_fe.DetailedResult
        """
        return sf.solve_detailed(model, position_rad, member_torque_Nm)

    def profiles(self, points_per_tooth: int):
        """The planet's and the ring's profiles, each about its own centre.

        Parameters
        ----------
        points_per_tooth : int
            Samples per tooth of each.

        Returns
        -------
        profiles : dict
            ``planet`` and ``ring``, (2, N) [m].
        checks : dict
            None for this pair ({}).
        """
        pair = self.pair
        phi1 = np.linspace(0, 2 * np.pi, pair.planet_teeth * points_per_tooth, endpoint=False)
        (ring,) = self.fixed_outlines(points_per_tooth)
        return {"planet": sg.planet_profile(pair, phi1), "ring": ring}, {}

    # -- the datasheet: supports --------------------------------------------------------
    def supports(self, declared) -> sp.Supports:
        """Rollers of the eccentric bearing on the eccentric (inner raceway of radius
        r_p, the output mechanism's ``eccentric_bearing_inner_radius``); no crankshafts.

        Parameters
        ----------
        declared : toothfem.si.SupportsSI

        Returns
        -------
        toothfem.fem.datasheet.supports.Supports
            Without an output mechanism r_p is ECCENTRIC_RACEWAY_REL r1.
        """
        om = self.output_mechanism
        r_in = (om.eccentric_bearing_inner_radius_m if om is not None
                else ECCENTRIC_RACEWAY_REL * self.pair.planet_pitch_radius_m)
        w = self.face_width_m
        return sp.resolved(declared, raceway_radius_m=r_in, roller_length_m=w,
                           outer_raceway=False,
                           crankshaft_diameter_m=2 * (r_in - self.pair.centre_distance_m),
                           crankshaft_span_m=(self.members + 2) * w)

    def system_mesh(self, pin_spring_m_per_N=None):
        """The planet's hats in the ring (:class:`toothfem.fem.system.mesh.ToothMesh`).

        Parameters
        ----------
        pin_spring_m_per_N : None
            The sine pair has no equal-springs limit.

        Returns
        -------
        toothfem.fem.system.mesh.ToothMesh

        Raises
        ------
        CaseError
            If ``pin_spring_m_per_N`` is given.
        """
        if pin_spring_m_per_N is not None:
            raise CaseError("pin_spring_m_per_N: the sine pair's contact is the FE's only")
        return ToothMesh(self)

    def system_model(self, supports, n_positions: int, **options):
        """The reducer's system model (:class:`toothfem.fem.drives.assembly.CycloidSystem`
        with the planet's mesh): the planet on its teeth, the eccentric bearing, the input
        shaft on its bearings and the output pins in the planet's holes.

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports
        n_positions : int
            Positions per meshing period.
        **options
            Go to the model.

        Returns
        -------
        toothfem.fem.drives.assembly.CycloidSystem

        Raises
        ------
        CaseError
            Without an output mechanism: nothing carries the torque to the output (the
            case check refuses such a case first, ``sine`` case_checks).
        """
        if self.output_mechanism is None:
            raise CaseError("sine: the planet has no output path (no [output_mechanism]): "
                            "no system model of the reducer")
        return CycloidSystem(self, supports, n_positions, **options)

    def sample_deviation(self, tolerances, rng) -> dv.SineDeviation:
        """Each flank of the planet and the ring off its profile, the crank's eccentricity
        off its nominal.

        Parameters
        ----------
        tolerances : toothfem.si.TolerancesSI
            ``tooth_profile_m`` and ``eccentricity_m`` are read.
        rng : numpy.random.Generator

        Returns
        -------
        toothfem.fem.deviations.SineDeviation
        """
        t, pair = tolerances, self.pair
        flank = tolerances.distribution_of("tooth_profile")
        return dv.SineDeviation(
            planet_profile=dv.symmetric(rng, t.tooth_profile_m, (pair.planet_teeth, 2), flank),
            ring_profile=dv.symmetric(rng, t.tooth_profile_m, (pair.ring_teeth, 2), flank),
            eccentricity=float(dv.symmetric(rng, t.eccentricity_m, 1,
                                            tolerances.distribution_of("eccentricity"))[0]))

    def nominal_deviation(self) -> dv.SineDeviation:
        """The pair as drawn (:meth:`SineDeviation.zero`).

        Returns
        -------
        toothfem.fem.deviations.SineDeviation
        """
        return dv.SineDeviation.zero(self.pair.planet_teeth, self.pair.ring_teeth)

    @property
    def pairing_period_pitches(self) -> int:
        """Z1 Z2: every planet tooth in every ring gap."""
        return self.pair.planet_teeth * self.pair.ring_teeth

    def member_frame_point(self, model, position_rad: float, point):
        """Ring-frame points about the planet's centre, turned back by its rotation.

        Parameters
        ----------
        model : toothfem.fem.sine_fe.SineFEModel
        position_rad : float
            [rad] of crank.
        point : array_like, shape (2,) or (2, N)
            [m].

        Returns
        -------
        numpy.ndarray
            Planet frame [m].
        """
        c, th = sg.planet_pose(model.pair, position_rad)
        pts = np.asarray(point, float)
        return rotate(pts - c.reshape((2,) + (1,) * (pts.ndim - 1)), -th[0])

    def fixed_outlines(self, points_per_tooth: int = 48) -> list:
        """The ring's tooth profile (one closed polyline, ring centre at the origin).

        Parameters
        ----------
        points_per_tooth : int
            Samples per ring tooth.

        Returns
        -------
        list of numpy.ndarray
            One (2, Zr points_per_tooth) polyline [m].
        """
        pair = self.pair
        phi = np.linspace(0, 2 * np.pi * pair.ring_teeth / pair.planet_teeth,
                          pair.ring_teeth * points_per_tooth, endpoint=False)
        return [sg.ring_profile(pair, phi)]

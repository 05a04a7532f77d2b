"""The cycloid disc on its pin ring: K-H-V cycloid drives and the second stage of RV-type
(2K-V) drives."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ...errors import CaseError
from ...geometry import cycloid as cy, cycloid_mesh as cym
from .. import cycloid_fe as cf
from .. import deviations as dv
from ..datasheet import supports as sp
from .assembly import CycloidSystem
from ..system.mesh import PinMesh
from .base import Drive, _merged_orders
from ...geometry.disc import disc_polygon
from ...si import CycloidStageSI, MaterialSI
from ...units import MM2_PER_M2

if TYPE_CHECKING:
    from ...layout import Layout
    from ..system.paths import OutputPath


@dataclass(frozen=True, kw_only=True)
class CycloidDrive(Drive):
    """A cycloid disc stage in SI (:class:`toothfem.si.CycloidStageSI`) with its train: the
    output ``path`` its layout builds (:mod:`toothfem.fem.system.paths`: ``Cranks`` of a
    2K-V drive, ``PinsInHoles`` of a K-H-V drive whose discs drive the output pins)."""
    stage: CycloidStageSI
    material_si: MaterialSI
    layout: Layout = field(compare=False, repr=False)
    path: OutputPath

    kind = "cycloid"
    member_name = "disc"
    contact_name = "pin"
    contacts_name = "pins"
    analytic_weight = "moment_arm"
    fe_options = {"pin_structure": cf.PIN_STRUCTURES}
    both_sides_options = {"sides": (1, -1)}
    both_flanks_options = {"sides": (0,)}

    @classmethod
    def from_case(cls, si, layout: Layout, path: OutputPath) -> CycloidDrive:
        """The drive of a case.

        Parameters
        ----------
        si : toothfem.si.CaseSI
            The case in SI (:meth:`toothfem.case.Case.to_si`).
        layout : toothfem.layout.Layout
            Its layout (K-H-V or RV).
        path : toothfem.fem.system.paths.OutputPath
            The layout's output path.

        Returns
        -------
        CycloidDrive

        Raises
        ------
        CaseError
            Without a [cycloid] or a [material] section.
        """
        if si.cycloid is None:
            raise CaseError(f"drive = {si.drive!r}: a [cycloid] section (disc and pins) is "
                            "required for the contact analyses of this drive")
        if si.material is None:
            raise CaseError("a [material] section is required for the contact analyses")
        return cls(stage=si.cycloid, material_si=si.material, layout=layout, path=path)

    @property
    def geometry(self) -> cy.CycloidGeometry:
        return self.stage.geometry

    @property
    def period_rad(self) -> float:
        return 2 * math.pi / self.geometry.pin_count

    @property
    def members(self) -> int:
        return self.stage.disc_count

    @property
    def load_factor(self) -> float:
        return self.stage.disc_load_factor

    @property
    def face_width_m(self) -> float:
        return self.stage.face_width_m

    @property
    def analytic_in_mesh_gap_m(self) -> float:
        """The seed's rigid split ignores modifications: every load-carrying pin shares."""
        return math.inf

    @property
    def output(self):
        """The output pins in the discs' holes, where the path has them (K-H-V)."""
        return self.path.output_mechanism

    @property
    def eccentric_race_radius_m(self) -> float:
        """The eccentric bearings' outer raceway, the path's: the crank hole (2K-V) or the
        centre bore (K-H-V) [m]."""
        return self.path.eccentric_race_radius_m(self.stage.holes)

    def members_torque(self, output_torque_Nm):
        """The discs' torque together, from the path's power flow
        (:meth:`toothfem.fem.system.paths.OutputPath.members_torque_per_output`): a 2K-V
        drive's pins turn the discs against the cranks, T (1 - 1/i)(Za/Zb); a K-H-V
        drive's discs are the output: T.

        Parameters
        ----------
        output_torque_Nm : float or numpy.ndarray
            [N m].

        Returns
        -------
        float or numpy.ndarray
            [N m].
        """
        return output_torque_Nm * self._members_torque_per_output

    @cached_property
    def _members_torque_per_output(self) -> float:
        return self.path.members_torque_per_output(self.speeds(), self.stage.lobe_count,
                                                   self.geometry.pin_count)

    def speeds(self) -> dict:
        """Per unit input speed, the path's (:meth:`~toothfem.fem.system.paths.OutputPath.
        speeds`: :func:`~toothfem.geometry.train.rv_speeds` of 2K-V,
        :func:`~toothfem.geometry.train.khv_speeds` of K-H-V).

        Returns
        -------
        dict of str to float
            input, crank, member (the disc), output (the carrier; K-H-V: the disc).
        """
        return self.path.speeds(self.stage.lobe_count, self.geometry.pin_count)

    def te_orders(self) -> dict:
        """Orders per output revolution at which a TE ripple is expected, in the cycloid's
        terms (:meth:`Drive.te_orders`; from :meth:`speeds`, the pins fixed):

        - ``output revolution`` (1): the output's runout, the encoders' eccentricity;
        - ``input revolution`` (|i|);
        - ``crank revolution`` and ``lobe passing (Zc)``: each pin meets the loaded zone
          once per crank turn against the pins and sees the Zc lobes go by in an output
          turn (the pins' errors; Zc for one pin more than lobes);
        - ``pin passing (Zp)``: each lobe meets the loaded zone once per turn of the crank
          against the disc, meeting the Zp pins in an output turn (the lobes' errors);
          ``eccentric against the disc``, the same order: an eccentric's own error (its
          eccentricity off the drawing, in the disc's bore) repeats once per that turn;
        - ``pin mesh``: the meshing period, Zp per crank turn;
        - the path's own (:meth:`~toothfem.fem.system.paths.OutputPath.te_orders`; 2K-V:
          ``first-stage mesh``, the sun's teeth per turn of the input against the carrier).

        Returns
        -------
        dict of str to float
            name -> order [per output revolution]; equal orders share one entry, their
            names joined by " = " (a K-H-V drive's crank is its input).
        """
        w = self.speeds()
        out = abs(w["output"])
        crank = abs(w["crank"]) / out
        pairs = [("output revolution", 1.0), ("input revolution", abs(w["input"]) / out),
                 ("crank revolution", crank), ("lobe passing (Zc)", crank),
                 ("pin passing (Zp)", abs(w["crank"] - w["member"]) / out),
                 ("eccentric against the disc", abs(w["crank"] - w["member"]) / out),
                 ("pin mesh", self.geometry.pin_count * crank)]
        return _merged_orders(pairs + self.path.te_orders(w))

    def meshing(self, positions_rad, crank_speed_rad_s: float = 1.0):
        """:func:`toothfem.geometry.cycloid.meshing` with the pins fixed.

        Conventional pins that turn in their grooves are handled by the friction rule of
        the efficiency model.

        Parameters
        ----------
        positions_rad : array_like, shape (P,)
            Crank angles [rad].
        crank_speed_rad_s : float
            [rad/s]; the sliding speed is the one at the disc.

        Returns
        -------
        toothfem.geometry.kinematics.MeshingState
        """
        return cym.meshing(self.geometry, positions_rad, crank_speed_rad_s, pin_motion="fixed")

    def fe_model(self, *, pin_structure: str | None = None, plane: str = "strain",
                 **unknown: object):
        """The disc, its pins and material as an FE model.

        Parameters
        ----------
        pin_structure : {"conventional", "integral", "rigid"}, optional
            Instead of the stage's.
        plane : {"strain", "stress"}
            The 2-D idealisation.
        **unknown
            None taken (:meth:`Drive.fe_model` takes any keyword; this model only the two
            above): a TypeError, as for any unexpected keyword.

        Returns
        -------
        toothfem.fem.cycloid_fe.CycloidFEModel

        Raises
        ------
        TypeError
            For any other keyword.
        """
        if unknown:
            raise TypeError("CycloidDrive.fe_model() got an unexpected keyword argument "
                            f"{next(iter(unknown))!r}")
        st, m = self.stage, self.material_si
        return cf.CycloidFEModel(
            geometry=st.geometry, holes=st.holes, youngs_modulus=m.youngs_modulus_Pa,
            poisson_ratio=m.poisson_ratio, face_width=st.face_width_m,
            pin_structure=pin_structure or st.pin_structure, plane=plane,
            housing_outer_radius=st.housing_outer_radius_m)

    def _new_cycle_solver(self, model, positions_rad, cache, **options):
        return cf.CycleSolver(model, positions_rad, cache=cache, **options)

    def solve_detailed(self, model, position_rad: float, member_torque_Nm: float):
        """:func:`toothfem.fem.cycloid_fe.solve_detailed` with its default refinement.

        Parameters
        ----------
        model : toothfem.fem.cycloid_fe.CycloidFEModel
        position_rad : float
            Crank angle [rad].
        member_torque_Nm : float
            Disc torque [N m].

        Returns
        -------
        toothfem.fem.cycloid_fe.DetailedResult
        """
        return cf.solve_detailed(model, position_rad, member_torque_Nm)

    def profiles(self, points_per_tooth: int):
        """The disc's working outline with its holes' polygon checks.

        Parameters
        ----------
        points_per_tooth : int
            Samples per lobe.

        Returns
        -------
        profiles : dict
            ``profile``: the (2, N) outline [m], disc frame.
        checks : dict
            ``disc_area_mm2`` and ``disc_polygon_valid``.
        """
        disc = disc_polygon(self.geometry, self.stage.holes,
                               points_per_lobe=points_per_tooth)
        return ({"profile": np.asarray(disc.exterior.coords).T[:, :-1]},
                {"disc_area_mm2": float(disc.area * MM2_PER_M2),
                 "disc_polygon_valid": bool(disc.is_valid)})

    # -- the datasheet: supports, full period, the second disc ----------------------------
    @property
    def full_period_pitches(self) -> int:
        """Pin pitches after which lobes, pins and holes repeat: at pitch m the contacts
        sit m lobes on from those of pitch 0 (docs/stiffness.md), so the model repeats
        after Za / gcd(Za, s) pitches, s the rotational symmetry of the hole pattern."""
        sym = self.stage.holes.symmetry
        return self.stage.lobe_count // math.gcd(self.stage.lobe_count, sym)

    def member_offsets(self, per_pitch: int, turns=None) -> tuple:
        """Disc j sits on eccentrics turned by 2 pi j / discs (Zb j / discs pitches); it is
        the first disc's part turned by i_j lobes more than the K-H-V pose at its crank
        angle, the smallest i_j that puts its crank holes on the cranks (K-H-V: its output
        pins' holes on the pins): (i_j - j/discs) s / Za whole, s those holes. Turning the
        part by i lobes moves its contacts i lobes back against its holes, so on the
        full-period grid disc j is the first disc at pitch Zb j / discs - i_j.

        Parameters
        ----------
        per_pitch : int
            Positions per pin pitch.
        turns : sequence of float, optional
            Each disc's eccentric phase in turns (default j / discs).

        Returns
        -------
        tuple of int
            Grid index of disc j, modulo the full period's positions.

        Raises
        ------
        CaseError
            If a disc's crank offset is off the grid, or no i_j exists.
        """
        zb, za, n = self.geometry.pin_count, self.stage.lobe_count, self.members
        sym = self.stage.holes.carrying_count
        k = self.full_period_pitches
        out = []
        turns = [j / n for j in range(n)] if turns is None else list(turns)
        for j, f in enumerate(turns):
            steps = zb * f * int(per_pitch)             # crank offset in grid steps
            if abs(steps - round(steps)) > 1e-9:
                raise CaseError(f"disc {j}: its crank offset of {f:g} turn is not on a grid "
                                f"of {per_pitch} positions per pin pitch; use a multiple of "
                                f"{n // math.gcd(n, zb * int(per_pitch))} positions per pitch")
            # turn psi = -phi_j/Za + i 2 pi/Za of the part must be a multiple of 2 pi/sym
            lobes = next((i for i in range(za) if _whole((i - f) * sym / za)), None)
            if lobes is None:
                raise CaseError(f"disc {j}: no turn of the first disc's part puts its "
                                f"{sym} crank holes on the cranks and its lobes on the pins")
            out.append(int(round(steps - lobes * int(per_pitch))) % (k * int(per_pitch)))
        return tuple(out)

    def supports(self, declared) -> sp.Supports:
        """Needle rollers in the crank holes (outer raceway the hole) on the cranks' eccentric
        journals (K-H-V: rollers in the centre bore on the input shaft's eccentrics);
        assumed crankshaft (input shaft): the journal's diameter less twice the
        eccentricity, on a span of the discs side by side plus one face width for each
        support bearing.

        Parameters
        ----------
        declared : toothfem.si.SupportsSI
            The case's bearing and crankshaft values (None: the assumption above).

        Returns
        -------
        toothfem.fem.datasheet.supports.Supports
        """
        g, w = self.geometry, self.face_width_m
        race = self.eccentric_race_radius_m
        d_roller = declared.bearing_roller_diameter_m or sp.ROLLER_DIAMETER_REL * race
        journal = 2 * (race - d_roller)
        return sp.resolved(declared, raceway_radius_m=race, roller_length_m=w,
                           crankshaft_diameter_m=journal - 2 * g.eccentricity_m,
                           crankshaft_span_m=(self.members + 2) * w,
                           carrier_stiffness_Nm_per_rad=self.pillar_carrier_Nm_per_rad())

    def pillar_carrier_Nm_per_rad(self) -> float | None:
        """A 2K-V carrier's pillars through the discs' pillar holes, each of the hole's
        radius less the eccentricity and a running gap (:data:`~toothfem.fem.datasheet.
        supports.PILLAR_GAP_M`), as long as the discs side by side, fixed in the output
        flange and the end plate: the series stiffness of
        :func:`~toothfem.fem.datasheet.supports.pillar_carrier_stiffness` (None without
        crank or pillar holes: the K-H-V drive's output is its pins, a rigid carrier).

        Returns
        -------
        float or None
            [N m/rad].
        """
        h = self.stage.holes
        if not (h.crank_hole_count and h.pillar_hole_count):
            return None
        d = 2 * (h.pillar_hole_radius_m - self.geometry.eccentricity_m - sp.PILLAR_GAP_M)
        if d <= 0:
            raise CaseError(
                f"cycloid.disc_holes.pillar_hole_radius_mm = {h.pillar_hole_radius_m * 1e3:.4g}"
                f" leaves no pillar: it must exceed the eccentricity "
                f"{self.geometry.eccentricity_m * 1e3:.4g} mm and a running gap of "
                f"{sp.PILLAR_GAP_M * 1e3:g} mm")
        m = self.material_si
        return sp.pillar_carrier_stiffness(h.pillar_hole_count, h.pillar_hole_circle_radius_m,
                                           d, self.members * self.face_width_m,
                                           m.youngs_modulus_Pa, m.poisson_ratio)

    def coupled_compliance(self, supports) -> dict:
        """The crankshafts: each a shaft on two simple supports (its carrier bearings)
        loaded by every disc's tangential force T_i/(n R_c) at the disc's axial place; disc
        j turns by the crank's deflection there over R_c (the pin resultants' share cancels
        over the n cranks).

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports
            Its crankshaft span and diameter.

        Returns
        -------
        dict
            ``crankshafts``: (discs, discs) [rad/(N m)]; {} for K-H-V (no crank holes: the
            discs' eccentrics sit on the one input shaft, whose bending is each disc's own
            support path).
        """
        h = self.stage.holes
        n, r_c = h.crank_hole_count, h.crank_hole_circle_radius_m
        if n == 0:
            return {}
        a = self.member_axial_positions_m(supports)
        m = self.material_si
        w = sp.simply_supported_influence(a[:, None], a[None, :], supports.crankshaft_span_m,
                                          supports.crankshaft_diameter_m,
                                          m.youngs_modulus_Pa, m.poisson_ratio)
        return {"crankshafts": w / (n * r_c ** 2)}

    def system_mesh(self, pin_spring_m_per_N=None):
        """Every disc on its pins (:class:`toothfem.fem.system.mesh.PinMesh`).

        Parameters
        ----------
        pin_spring_m_per_N : float, optional
            Equal contact springs instead of the FE (the hand models' limit) [m/N].

        Returns
        -------
        toothfem.fem.system.mesh.PinMesh
        """
        return PinMesh(self, pin_spring_m_per_N)

    def system_model(self, supports, n_positions: int, **options):
        """The cycloid reducer's system model on its path
        (:class:`toothfem.fem.drives.assembly.CycloidSystem`).

        Parameters
        ----------
        supports : toothfem.fem.datasheet.supports.Supports
        n_positions : int
            Positions per pin pitch.
        **options
            Go to the model.

        Returns
        -------
        toothfem.fem.drives.assembly.CycloidSystem
        """
        return CycloidSystem(self, supports, n_positions, **options)

    def sample_deviation(self, tolerances, rng) -> dv.CycloidDeviation:
        """Pins off their true positions and the pin circle off its radius (one value for
        the ring), pin diameters within their limits, each lobe flank off its profile, the
        disc's profile off its crank holes (the mean of the holes' offsets: a best fit of
        the disc on its cranks; its turn goes into the rigid rotation), the crank's
        eccentricity off its nominal.

        Parameters
        ----------
        tolerances : toothfem.si.TolerancesSI
        rng : numpy.random.Generator

        Returns
        -------
        toothfem.fem.deviations.CycloidDeviation
        """
        t, dist = tolerances, tolerances.distribution_of
        zb, za = self.geometry.pin_count, self.stage.lobe_count
        radial = cym.pin_centres(self.geometry) / self.geometry.pin_circle_radius_m
        offset = dv.in_zone(rng, t.pin_position_m, zb, dist("pin_position")) \
            + radial * dv.symmetric(rng, t.pin_circle_radius_m, 1, dist("pin_circle_radius"))
        holes = dv.in_zone(rng, t.crank_hole_position_m, self.stage.holes.crank_hole_count,
                           dist("crank_hole_position"))
        return dv.CycloidDeviation(
            pin_offset=offset,
            pin_radius=0.5 * dv.between(rng, t.pin_diameter_lower_m, t.pin_diameter_upper_m,
                                        zb, dist("pin_diameter")),
            profile=dv.symmetric(rng, t.disc_profile_m, (za, 2), dist("disc_profile")),
            # a K-H-V disc has no crank holes: its bore locates it (no tolerance key)
            member_offset=-np.mean(holes, axis=1) if holes.size else np.zeros(2),
            eccentricity=float(dv.symmetric(rng, t.eccentricity_m, 1,
                                            dist("eccentricity"))[0]))

    def pin_ring_offsets(self, order: int, radial_m: float = 0.0,
                         tangential_m: float = 0.0) -> np.ndarray:
        """The pins' centres off their places in one order round the ring: pin j at angle
        theta_j moved by cos(order theta_j) (radial_m outward + tangential_m along
        +theta). Order 1 tangential is the ring's cumulative pitch error (an indexing
        error), order 2 radial its ovality; order 1 radial with order 1 tangential of the
        opposite phase is the ring's centre moved.

        Parameters
        ----------
        order : int
            >= 1, waves round the ring.
        radial_m, tangential_m : float
            Amplitudes [m].

        Returns
        -------
        numpy.ndarray, shape (2, Zb)
            Housing frame [m], for ``CycloidDeviation.pin_offset``.

        Raises
        ------
        CaseError
            For an order below 1.
        """
        if int(order) != order or order < 1:
            raise CaseError(f"pin ring order = {order!r}: a whole number >= 1")
        c = cym.pin_centres(self.geometry)
        radial = c / np.linalg.norm(c, axis=0)
        along = np.stack([-radial[1], radial[0]])
        wave = np.cos(int(order) * np.arctan2(c[1], c[0]))
        return (radial_m * radial + tangential_m * along) * wave

    def nominal_deviation(self) -> dv.CycloidDeviation:
        """The stage as drawn (:meth:`CycloidDeviation.zero`).

        Returns
        -------
        toothfem.fem.deviations.CycloidDeviation
        """
        return dv.CycloidDeviation.zero(self.geometry.pin_count, self.stage.lobe_count)

    def deviation_period_pitches(self, deviation) -> int:
        """Pin pitches after which a built stage's model repeats: at pitch m pin j + m and
        lobe l + m take the places of pin j and lobe l, so pins that differ repeat after Zb
        pitches, lobes (or the disc's profile off its bore) after Za, a 2K-V crank's own
        errors after its turn against the carrier (Za); each with the full period of the
        holes. Deviations alike at every pin or lobe (an eccentricity error, one radius
        change of every pin, one flank's material on every lobe) change nothing.

        Parameters
        ----------
        deviation : toothfem.fem.deviations.CycloidDeviation or None

        Returns
        -------
        int
        """
        k = self.full_period_pitches
        if deviation is None:
            return k
        d = deviation
        pr = np.asarray(d.pin_radius, float)
        if np.any(d.pin_offset) or (pr.size and np.ptp(pr) > 0):
            k = math.lcm(k, self.geometry.pin_count)
        prof = np.asarray(d.profile, float)
        if np.any(d.member_offset) or (prof.size and np.any(np.ptp(prof, axis=0) > 0)):
            k = math.lcm(k, self.stage.lobe_count)
        return self.path.with_crank_period(k, self, d)

    @property
    def pairing_period_pitches(self) -> int:
        """Zb Za: at pitch m pin j + m meets lobe l + m, so pin and lobe indices return
        together after lcm(Zb, Za) = Zb Za pitches (Zb = Za + 1)."""
        return self.geometry.pin_count * self.stage.lobe_count

    def member_frame_point(self, model, position_rad: float, point):
        """Points in the disc frame (:func:`toothfem.geometry.cycloid.to_disc_frame`).

        Parameters
        ----------
        model : toothfem.fem.cycloid_fe.CycloidFEModel
        position_rad : float
            [rad].
        point : array_like, shape (2,) or (2, N)
            [m].

        Returns
        -------
        numpy.ndarray
            [m], the input's shape.
        """
        pts = np.asarray(point, float)
        local = cym.to_disc_frame(model.geometry, [position_rad], pts.reshape(2, 1, -1))
        return local[:, 0, :].reshape(pts.shape)

    def fixed_outlines(self, points_per_tooth: int = 48) -> list:
        """Each pin's circle (pin j centred at angle 2 pi j / Zb).

        Parameters
        ----------
        points_per_tooth : int
            Points on each circle.

        Returns
        -------
        list of numpy.ndarray
            Zb (2, points_per_tooth) circles [m].
        """
        g = self.geometry
        t = np.linspace(0.0, 2 * math.pi, points_per_tooth, endpoint=False)
        circle = g.pin_radius_m * np.stack([np.cos(t), np.sin(t)])
        return [c[:, None] + circle for c in cym.pin_centres(g).T]


def _whole(x: float, tol: float = 1e-9) -> bool:
    """x is an integer within ``tol``."""
    return abs(x - round(x)) < tol

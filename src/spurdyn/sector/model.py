"""The sector model of a run, built once (docs/sector.md, section 6): the bodies (modal or
whole), the contacts (drive and back flanks, tip corners off the path), the mesh damper and
the loading, from the pair and the run settings.

Every time integrator in every backend steps the same :class:`SectorModel`
(:mod:`spurdyn.solvers.sector.stepper`): the implicit loop with its bodies factorised for
``S = M + gamma' C + beta' K``, the RK4 reference with ``gamma' = beta' = 0`` (its ``S`` is
``M``). The NumPy loops read its methods (:meth:`SectorModel.rows_at`, :meth:`gap_rows`,
:meth:`compliance` ...), the compiled loops its typed packs (:meth:`SectorModel.packs`),
the twins of those methods in :mod:`spurdyn.solvers.sector.rows_compiled`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from spurdyn.contact.hertz import effective_modulus, strip_quadrature
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.model.alpha import GeneralizedAlpha
from spurdyn.model.loading import check_history, hub_torques, static_force
from spurdyn.sector.bearings import TRANSLATIONS, hub_bearings
from spurdyn.sector.bodies import FullBody, ModalBody
from spurdyn.sector.cache import cached
from spurdyn.sector.cyclic import statics_body
from spurdyn.sector.damper import mesh_damper_table
from spurdyn.sector.faces import crack_faces
from spurdyn.sector.fault_bodies import (GearFaults, any_split, check_cracked_flanks, cracked_meshes, faulty_cycles_of,
                                         no_faults, run_faults, split_rows, strip_excess)
from spurdyn.sector.lcp import Rows
from spurdyn.sector.packs import SectorConfig, SectorContacts
from spurdyn.sector.reduced import reduce_gear
from spurdyn.sector.rules import (
    CYCLE_POSITIONS,
    KEEP_FREQUENCY,
    back_flanks_on,
    body_rayleigh,
    cover_cycles,
    cycles_limit,
    mesh_damping,
    steps_per_cycle,
    with_defaults,
)
from spurdyn.sector.state import common_rotation, unpack_state
from spurdyn.sector.statics import contact_law, driving_pair, mesh_cycle, pairs_in_path, solve_position
from spurdyn.sector.system import (
    REACH,
    WHOLE_FROM_CYCLES,
    back_roll_sum,
    back_teeth,
    contact_radii,
    covered_turns,
    gap_table,
    gear_block,
    half_widths,
    half_widths_at,
    teeth_for,
)
from spurdyn.settings import RunSettings, refuse_sector_row_grading


@dataclass(frozen=True)
class Start:
    """Where a run starts: ``q``, ``v``, the scheme's accelerations ``acc`` and ``qdd``, the
    contacts' ``force``, the driver's body tooth ``offset`` of pair 0, and for a
    continuation how far its common rotation was ``reset`` (a fraction of the speed)."""

    q: NDArray[np.float64]
    v: NDArray[np.float64]
    acc: NDArray[np.float64]
    qdd: NDArray[np.float64]
    force: NDArray[np.float64]
    offset: int
    reset: float | None


class SectorModel:
    """The sector model of one run (module docstring), built once by :meth:`build`.

    Attributes hold the pair as driven (``dp``, its base radii ``ra``, ``rb``, the
    ``pitch``), the run (``speed``, ``per_cycle`` steps a cycle of ``h`` s, ``cycles`` and
    at most ``most``), the two gears' ``blocks`` and bodies (``gears``, ``modes`` true for
    modal ones; ``parts`` their coordinates), the contacts (``teeth`` the drive flanks' driver
    teeth, ``back_k`` the back flanks', ``c_teeth``, ``c_side`` all of them), the
    quasi-static ``cycle``, the strips' ``law`` and ``c_h``, the mesh damper's ``c_table``,
    the rigid gap's ``table`` and the turns ``theta_lo .. theta_hi`` the contacts cover."""

    def __init__(self, pair: GearPair, settings: RunSettings, scheme: tuple[float, float, float, float, float, float],
                 per_cycle: int, modes: bool | float) -> None:
        dp = self.dp = driving_pair(pair)
        self.pair, self.settings = pair, settings
        ga, gb = dp.gear_a, dp.gear_b
        self.ra, self.rb = ga.base_radius, gb.base_radius
        # a faulty pair repeats after a revolution: it runs whole ones, at least FAULTY_PERIODS
        self.period = faulty_cycles_of(dp, pair.driver, settings.faults)
        self.cycles, self.most = whole_periods(int(with_defaults(settings).cycles), cycles_limit(settings),
                                                self.period, settings.max_cycles is None)
        self.speed = float(settings.speed_a if pair.driver == "a" else settings.speed_b)
        self.pitch = pitch = 2.0 * math.pi / ga.teeth
        self.per_cycle = per_cycle
        self.h = pitch / self.speed / per_cycle
        # the cycles' worth of teeth the run carries (a guard stops the run where they are left)
        cover = max(cover_cycles(settings), cover_cycles(settings, self.most))
        self.back = back = back_flanks_on(dp, settings)
        (first_a, count_a), (first_b, count_b) = teeth_for(dp, cover, back, settings.teeth)
        mesh_keys = (settings.nx, settings.ny, settings.grading)
        self.faults = faults = run_faults(pair, settings, ((first_a, count_a), (first_b, count_b)))
        self.splits = any_split(faults)     # a spall over part of the face width splits its pairs
        self.blocks = blocks = tuple(
            _block(dp, g, sense, first, count, mesh_keys, faults[g] if faults else None)
            for g, (sense, first, count) in enumerate(((1.0, first_a, count_a), (-1.0, first_b, count_b))))
        self.load = static_force(pair, settings.torque)
        self.estar = effective_modulus(ga.material.young, ga.material.poisson, gb.material.young,
                                       gb.material.poisson)
        self.width = min(ga.face_width, gb.face_width)
        if faults:      # the lowest contacts, off the path by the reach, under 5 times the load
            ends = np.array([dp.start_roll_a - REACH * pitch, dp.end_roll_a + REACH * pitch])
            radii = contact_radii(dp, ends)
            wide = float(np.max(half_widths(dp, ends, np.full(2, 5.0 * self.load), self.estar, self.width)))
            check_cracked_flanks(blocks, faults, (float(radii[0].min()), float(radii[1].min())), wide)
        # the driver's teeth that come near the path: 0 .. P at the start, one more a cycle (of
        # as many as the run may go on to; the result keeps those of the cycles it ran)
        self.teeth = teeth = np.arange(-cover - 1, pairs_in_path(dp) + 1)
        # the contacts: the drive flanks of those teeth, and with the back flanks those of the
        # driver's teeth that come near the back path (each on the driven gear's tooth -k + 1)
        self.jn = dp.backlash_normal
        self.sigma = back_roll_sum(dp)
        self.back_lo, self.back_hi = back_teeth(dp, cover, REACH * pitch) if back else (0, -1)
        self.back_k = np.arange(self.back_lo, self.back_hi + 1)
        self.c_teeth = np.concatenate([teeth, self.back_k]).astype(np.intp)
        self.c_side = np.concatenate([np.zeros(teeth.size, np.intp), np.ones(self.back_k.size, np.intp)])
        # generalized-alpha's alpha_m, alpha_f, beta, gamma, beta', gamma' (zeros for RK4)
        self.am, self.af, self.beta, self.gamma, self.bp, self.gp = scheme
        self.rayleigh = rayleigh = body_rayleigh(settings)
        self.modes = bool(modes)
        if modes:
            top = KEEP_FREQUENCY if modes is True else float(modes)
            self.gears: tuple[Any, Any] = tuple(
                ModalBody(cached(("modes", blk.gear, blk.sense, blk.first, blk.count, *mesh_keys, top,
                                  blk.missing, faults[g].meshed if faults else ()),
                                 lambda blk=blk: reduce_gear(blk, top)), self.gp, self.bp, rayleigh,
                          2 if back else 1)
                for g, blk in enumerate(blocks))
        else:
            self.gears = tuple(FullBody(blk, self.gp, self.bp, rayleigh) for blk in blocks)
        # a crack's faces, a unilateral contact of their own (faulty gears are modal bodies)
        self.faces = crack_faces(faults, blocks, self.gears, 2 if back else 1) if self.modes else None
        # the quasi-static cycle's bodies: a cyclic reduction's flank flexibility, or the FE body;
        # a faulty gear's healthy twin (the start and the mesh damper are the healthy pair's)
        bodies = tuple(_block(dp, g, blk.sense, blk.first, blk.count, mesh_keys, None).body
                       if faults and faults[g].any else statics_body(self.gears[g])
                       for g, blk in enumerate(blocks))
        self.na = na = self.gears[0].n
        self.n = n = na + self.gears[1].n
        self.parts = (slice(0, na), slice(na, n))
        # the hubs on bearings: their translations after the bodies (none without)
        self.bear = hub_bearings(settings.bearings, pair.driver, dp.working_pressure_angle, blocks, self.gp,
                                 self.bp, self.whole)
        self.nt = TRANSLATIONS if self.bear is not None else 0
        self.n = n + self.nt
        self.tpart = slice(n, n + self.nt)
        self.cycle = cached(("cycle", pair, settings.torque, first_a, count_a, first_b, count_b, *mesh_keys),
                            lambda: mesh_cycle(pair, settings.torque, settings.nx, settings.ny,
                                               positions=CYCLE_POSITIONS, bodies=bodies))
        self.law = contact_law(pair, settings.torque, bodies)
        self.c_h = self.law.c_h
        self.z_theta = []
        for g in range(2):
            e = np.zeros(self.gears[g].n)
            e[0] = 1.0
            self.z_theta.append(self.gears[g].solve(e))
        self.c_table = mesh_damper_table(self.cycle, mesh_damping(settings)[0],
                                         reduced_mass(blocks[0].inertia, blocks[1].inertia, self.ra, self.rb), pitch)
        self.reach = reach = REACH * pitch
        self.theta_lo, self.theta_hi = covered_turns(dp, (int(teeth[0]), int(teeth[-1])),
                                                     (self.back_lo, self.back_hi) if back else None, reach)
        self.table = cached(("gaps", pair, reach), lambda: gap_table(dp, reach))
        self.roll_0, self.roll_1 = dp.start_roll_a, dp.end_roll_a

    @classmethod
    def build(cls, pair: GearPair, settings: RunSettings, *, integrator: str = "implicit",
              dt: float | None = None, modes: bool | float | None = None) -> SectorModel:
        """The model of a run of ``integrator`` (``"implicit"``: bodies for generalized-alpha at
        ``settings.rho_inf``; ``"rk4"``: bodies for ``M^-1``) at the step ``dt`` (by default
        :func:`~spurdyn.sector.rules.steps_per_cycle`'s; shortened to a whole number
        a mesh cycle); ``modes`` as :func:`~spurdyn.solvers.sector.run.simulate_sector` reads it."""
        refuse_sector_row_grading(settings.row_grading)
        settings = with_defaults(settings)
        check_history(pair, settings)
        speed = float(settings.speed_a if pair.driver == "a" else settings.speed_b)
        per_cycle = steps_per_cycle(speed, driving_pair(pair).gear_a.teeth, dt)
        if modes is None:
            modes = settings.bodies == "modal"
        if integrator == "rk4":
            return cls(pair, settings, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0), per_cycle, modes)
        scheme = GeneralizedAlpha(settings.rho_inf)
        h = 2.0 * math.pi / driving_pair(pair).gear_a.teeth / speed / per_cycle
        return cls(pair, settings, (scheme.alpha_m, scheme.alpha_f, scheme.beta, scheme.gamma,
                                    scheme.beta_prime(h), scheme.gamma_prime(h)), per_cycle, modes)

    @property
    def whole(self) -> bool:
        """Both gears whole (the compiled loops' bodies, a continuation's start)."""
        return self.blocks[0].whole and self.blocks[1].whole

    # -- the loading and the start --------------------------------------------------------
    def torques(self, t: Any) -> NDArray[np.float64]:
        """The hubs' torques at times ``t`` (s; driver first, as ``dp``'s A and B)."""
        tq = hub_torques(self.pair, self.settings, t)
        return tq[..., ::-1].copy() if self.pair.driver == "b" else tq

    def torques_at(self, steps: NDArray[np.intp]) -> NDArray[np.float64]:
        """The hubs' torques at the ends of the run's ``steps``."""
        return self.torques(steps * self.h)

    def start(self) -> Start:
        """The state at ``t = 0``: another run's end (``settings.start_state``), rest (the
        bodies undeformed, the torques ramped up), or the static equilibrium of the loaded
        pair at the start of a cycle; the hubs at their nominal speeds."""
        n, na, speed, ra, rb = self.n, self.na, self.speed, self.ra, self.rb
        if self.settings.start_state is not None:
            return self._continued()
        q, qdd, acc, force, v = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(self.c_teeth.size), np.zeros(n)
        v[0], v[na] = speed, speed * ra / rb
        if self.settings.start == "rest":
            return Start(q, v, acc, qdd, force, 0, None)
        dp = self.dp
        # a missing tooth's pair carries nothing: the others share the load
        js, f0, e0, _, _ = solve_position(self.law, dp.start_roll_a, self._made_contacts)
        rolls0 = [dp.start_roll_a + j * self.pitch for j in js]
        hw0 = half_widths(dp, rolls0, f0, self.estar, self.width)     # the strips of the static forces
        for g, blk in enumerate(self.blocks):
            sign = 1 if g == 0 else -1
            loads = np.zeros(blk.mass.size)
            for j, r, b, fj in zip(js, contact_radii(dp, rolls0)[g], hw0, f0):
                if fj:
                    # added at each place: a chipped flank's cut node stands in for several
                    np.add.at(loads, blk.flank_dofs(sign * j), fj * blk.flank_load(sign * j, float(r), float(b)))
            q[self.parts[g]][1:] = self.gears[g].static(loads)
        q[0] = e0 / ra
        if self.bear is not None:   # the hubs at their bearings' static deflection, the driver on by it
            q[self.tpart] = self.bear.static(float(np.sum(f0)))
            q[0] += float(self.bear.rows[0] @ q[self.tpart]) / ra
        force[np.searchsorted(self.teeth, js)] = f0      # the drive flanks come first
        return Start(q, v, acc, qdd, force, 0, None)

    def _continued(self) -> Start:
        """Another run's end (a sweep's continuation): its state per angle at this speed."""
        if not self.whole:
            raise InputError("start_state", "a sector run starts from another's end only on whole "
                             f"gears: give {WHOLE_FROM_CYCLES} cycles or more, and no fewer teeth than "
                             "the gears have")
        if self.bear is not None:
            raise InputError("start_state", "a run with bearings starts from rest or a static state: "
                             "another run's end does not carry its hubs' translations")
        if self.faces is not None or self.splits:
            raise InputError("start_state", "a run with a cracked tooth or a spall over part of the face width starts from "
                             "rest or a static state: another run's end does not carry the crack faces' or pit strips' forces")
        speed, na, parts = self.speed, self.na, self.parts
        st = unpack_state(self.settings.start_state, self.n)
        q, v, acc, qdd = st.q.copy(), speed * st.dq, speed**2 * st.ddq, speed**2 * st.qdd
        force = np.zeros(self.c_teeth.size)
        at = dict(zip(zip(st.teeth.tolist(), st.sides.tolist()), st.forces))
        force[:] = [at.get((int(k) + st.offset, int(sd)), 0.0) for k, sd in zip(self.c_teeth, self.c_side)]
        # the pair's common rotation at this point's speed (a chain's drift not carried on)
        common = common_rotation(tuple(self.gears[g].momentum(v[parts[g]]) for g in range(2)),
                                 (self.blocks[0].inertia, self.blocks[1].inertia), self.ra / self.rb, speed)
        v[0] += common
        v[na] += common * self.ra / self.rb
        return Start(q, v, acc, qdd, force, st.offset, common / speed)

    # -- the contacts at a step (NumPy; compiled twins in rows_compiled) ------------------
    def rows_at(self, theta_a: float, f: NDArray[np.float64], offset: int = 0,
                pit: NDArray[np.float64] | None = None) -> Rows | None:
        """The contacts near their paths at the driver's turn ``theta_a``: their indices in
        ``c_teeth``, the constant part of their gaps, and per gear the rows' coefficients on
        the hub and their elastic parts (the bodies' ``rows``), the strips' half-widths those
        of the forces ``f``. A back flank's roll is ``Sigma - rho``
        (:func:`~spurdyn.sector.system.back_roll_sum`), running backwards as the
        driver turns, and its gap the mirror image's plus the backlash (docs/sector.md, 6.7);
        ``offset`` the driver's body tooth of pair 0 (a continuation runs on); ``pit`` the
        pit strips' forces of the step before where a pit over part of the face width split
        a contact (-1 elsewhere; none: no contact was split), which splits it into two rows
        (:class:`~spurdyn.sector.lcp.Rows`)."""
        rolls, near = self._rolls(theta_a, offset)
        on = np.flatnonzero(near)
        if not on.size:
            return None
        return self._pair_rows(on, rolls[on], f[on], theta_a, offset, None if pit is None else pit[on])

    def rows_many(self, theta_a: NDArray[np.float64], f: NDArray[np.float64],
                  offset: int = 0, full: bool = True) -> tuple[NDArray[np.intp], Rows] | None:
        """:meth:`rows_at` of several states at once, the driver's turns ``theta_a`` ``(S,)``
        and forces ``f`` ``(S, C)``: ``(sample, rows)``, one entry a contact near its path in
        a state, ``rows.on`` its index in ``c_teeth`` and ``sample`` its state's (in the
        states' order, each state's contacts in :meth:`rows_at`'s, a split pair's two rows
        naming it twice); entry by entry :meth:`rows_at`'s numbers. ``None`` where none is near.
        ``full`` false: the bodies' rows without their elastic parts (the bodies' ``rows``)."""
        theta_a = np.asarray(theta_a, dtype=float)
        rolls, near = self._rolls(theta_a[:, None], offset)
        sample, on = np.nonzero(near)
        if not on.size:
            return None
        rows = self._pair_rows(on, rolls[sample, on], f[sample, on], theta_a[sample], offset, full=full)
        return (sample if rows.on.size == on.size else sample[np.cumsum(rows.kind != 2) - 1]), rows

    def near_many(self, theta_a: NDArray[np.float64], offset: int = 0) -> NDArray[np.intp]:
        """``(S,)`` how many contacts :meth:`rows_many` gives in each state of the driver's
        turns ``theta_a`` ``(S,)``: those near their paths (and made)."""
        return self._rolls(np.asarray(theta_a, dtype=float)[:, None], offset)[1].sum(axis=1)

    def _rolls(self, theta_a: Any, offset: int) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Every contact's roll at the driver's turn ``theta_a`` (a number, or ``(S, 1)``
        for several) and whether it is near its path and made (:meth:`made`)."""
        rolls = self.roll_0 + theta_a + self.c_teeth * self.pitch
        rolls = np.where(self.c_side == 1, self.sigma - rolls, rolls)
        near = (rolls >= self.roll_0 - self.reach) & (rolls <= self.roll_1 + self.reach)
        if self.faults:
            near &= self.made(self.c_teeth + offset, self.c_side) & ~self.lost(self.c_teeth + offset, self.c_side, rolls)
        return rolls, near

    def _pair_rows(self, on: NDArray[np.intp], rolls: NDArray[np.float64], f: NDArray[np.float64],
                   theta_a: Any, offset: int, pit: NDArray[np.float64] | None = None, full: bool = True) -> Rows:
        """The :class:`Rows` of the contacts ``on`` at their ``rolls`` under their forces
        ``f`` (their pit strips' ``pit``, :meth:`rows_at`), the driver at ``theta_a`` (a
        number, or one per contact); without the bodies' modal rows unless ``full``."""
        ra, rb = self.ra, self.rb
        kind, share, extra = np.zeros(on.size, np.intp), np.ones(on.size), 0.0
        if self.splits:
            places = self.flank_places(self.c_teeth[on] + offset, self.c_side[on])
            idx, kind, share, extra, f = split_rows(self.faults, places, self.c_side[on], rolls, f,
                                                    np.full(on.size, -1.0) if pit is None else pit)
            on, rolls, theta_a = on[idx], rolls[idx], theta_a if np.ndim(theta_a) == 0 else theta_a[idx]
        g0, slope, r_a, r_b = self.table.at(rolls)
        hw = half_widths_at(self.dp, (r_a, r_b), f, self.estar, self.width * share)
        sd = self.c_side[on]
        sgn = np.where(sd == 1, -1.0, 1.0)        # d roll / d theta_A
        k = self.c_teeth[on] + offset
        if self.faults:
            g0 = g0 + self.pit_gaps(k, sd, rolls) + extra
        # d gap / d theta: the base circles' and, off the path, the corner's
        sides = tuple((coef, self.gears[g].rows(kg, self.blocks[g].flank_loads(r, hw), sd, full))
                      for g, (kg, coef, r) in enumerate(((k, sgn * (slope - ra), r_a),
                                                          (-k + sd, sgn * rb, r_b))))
        return Rows(on, g0 - sgn * slope * theta_a + self.jn * sd, sides, kind, share, f)

    def flank_places(self, k: NDArray[np.intp], sd: NDArray[np.intp]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
        """The contacts' places in each whole body (from its first tooth) for the driver's
        body teeth ``k`` on flanks ``sd``."""
        b0, b1 = self.blocks
        return (k - b0.first) % b0.count, (-k + sd - b1.first) % b1.count

    def made(self, k: NDArray[np.intp], sd: NDArray[np.intp]) -> NDArray[np.bool_]:
        """Whether the contacts of the driver's body teeth ``k`` on flanks ``sd`` are made
        (neither tooth missing; twin in ``rows_compiled.contact_rows``)."""
        at0, at1 = self.flank_places(k, sd)
        return (self.faults[0].gone[at0] == 0) & (self.faults[1].gone[at1] == 0)

    def lost(self, k: NDArray[np.intp], sd: NDArray[np.intp], rolls: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether those contacts lie, at their rolls on the path ``rolls`` (broadcast with
        ``k``), where a chip took their flank (twin in ``rows_compiled.contact_rows``)."""
        out = np.zeros(np.broadcast(k, rolls).shape, dtype=bool)
        for gf, at in zip(self.faults, self.flank_places(k, sd)):
            span = gf.lost[at, sd]
            out |= (span[..., 0] < rolls) & (rolls < span[..., 1])   # open: the cut itself is kept, as the statics keep it
        return out

    def pit_gaps(self, k: NDArray[np.intp], sd: NDArray[np.intp], rolls: NDArray[np.float64]) -> NDArray[np.float64]:
        """The pits' extra gaps (m) of those contacts at their rolls on the path ``rolls``
        (twin: ``rows_compiled.pit_gap``)."""
        out = np.zeros(rolls.size)
        for gf, at in zip(self.faults, self.flank_places(k, sd)):
            pit = gf.pits[at, sd]
            out += np.where((pit[:, 3] >= 1.0) & (pit[:, 0] <= rolls) & (rolls <= pit[:, 1]), pit[:, 2], 0.0)
        return out

    def _made_contacts(self, js: list[int], roll_a: NDArray[np.float64], roll_b: NDArray[np.float64]) -> list[Any]:
        """The static start's contacts (:data:`~spurdyn.sector.statics.Contacts`): every pair
        on the path whose teeth are both there."""
        ks, sd = np.asarray(js, np.intp), np.zeros(len(js), np.intp)
        made = self.made(ks, sd) & ~self.lost(ks, sd, np.asarray(roll_a, dtype=float)) if self.faults \
            else [True] * len(js)
        return [(j, 1.0, 0.0) for j, ok in zip(js, made) if ok]

    def gap_rows(self, rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``G x`` for the pairs ``rows`` (their constant parts not included)."""
        return sum(coef * x[self.parts[g]][0] + self.gears[g].elastic(elastic, x[self.parts[g]])
                   for g, (coef, elastic) in enumerate(rows.sides)) + self._translated(rows, x)

    def _translated(self, rows: Rows, x: NDArray[np.float64]) -> Any:
        """``T x_t``: the rows' translation part of ``x`` (0 without bearings)."""
        return self.bear.of(self.c_side[rows.on]) @ x[self.tpart] if self.bear is not None else 0.0

    def rigid_rows(self, rows: Rows, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``D x``: the rows' rigid part alone, their entries on the hubs' turns and translations (the mesh damper's
        rows: ``-D q_dot`` is the rate of the pairs' whole approach while they touch)."""
        return sum(coef * x[self.parts[g]][0] for g, (coef, _) in enumerate(rows.sides)) + self._translated(rows, x)

    def compliance(self, rows: Rows) -> tuple[Any, ...]:
        """``(G S^-1 G^T, G S^-1 D^T, D S^-1 D^T, C_res, S^-1 G^T)``: the pairs' coupling
        through each gear by their whole rows ``G`` and their rigid parts ``D`` (``S^-1 D^T``
        is the hub's response ``z`` times the rows' hub coefficients); the bodies' residual
        compliance between the pairs' loads; and the columns (per gear)."""
        m = rows.on.size
        w, w_gd, w_dd, res = (np.zeros((m, m)) for _ in range(4))
        cols = []
        for g, (coef, elastic) in enumerate(rows.sides):
            z, body = self.z_theta[g], self.gears[g]
            full = np.outer(z, coef) + body.columns(elastic)       # S^-1 G^T
            w += coef[:, None] * full[0][None, :] + body.elastic(elastic, full)
            w_gd += np.outer(coef * z[0] + body.elastic(elastic, z), coef)
            w_dd += z[0] * np.outer(coef, coef)
            res += body.residual(elastic)
            cols.append(full)
        if self.bear is not None:       # the translations' block, its own (S_tt diagonal)
            tr = self.bear.of(self.c_side[rows.on])
            tt = (tr * self.bear.tinv) @ tr.T
            w += tt
            w_gd += tt
            w_dd += tt
            cols.append(self.bear.tinv[:, None] * tr.T)
        return w, w_gd, w_dd, res + strip_excess(rows.kind, rows.share, self.c_h), cols

    def contact_compliance(self, rows: Rows) -> NDArray[np.float64]:
        """``C_s = c_H I + b_i^T R b_j``: the pairs' compliance without inertia (RK4's)."""
        res = sum(self.gears[g].residual(el) for g, (_, el) in enumerate(rows.sides))
        return res + strip_excess(rows.kind, rows.share, self.c_h) + self.c_h * np.eye(rows.on.size)


    def columns_times(self, cols: list[NDArray[np.float64]], lam: NDArray[np.float64]) -> NDArray[np.float64]:
        """``S^-1 G^T lam`` from the per-gear columns ``cols``."""
        return np.concatenate([c @ lam for c in cols])

    def rigid_columns_times(self, rows: Rows, lam: NDArray[np.float64]) -> NDArray[np.float64]:
        """``S^-1 D^T lam``: the responses to the hub torques of the rows' rigid parts."""
        out = [float(coef @ lam) * self.z_theta[g] for g, (coef, _) in enumerate(rows.sides)]
        if self.bear is not None:
            out.append(self.bear.tinv * (self.bear.of(self.c_side[rows.on]).T @ lam))
        return np.concatenate(out)

    # -- the compiled loops' packs ---------------------------------------------------------
    def packs(self, offset: int = 0) -> tuple[Any, ...]:
        """``(gear A, gear B, contacts, gap table, config)``: the typed packs of
        :mod:`spurdyn.sector.packs` the compiled loops read (modal bodies of whole gears)."""
        xq, wq = strip_quadrature()
        faults = self.faults or tuple(no_faults(blk.count) for blk in self.blocks)
        contacts = SectorContacts(np.asarray(self.c_teeth, np.int64), np.asarray(self.c_side, np.int64),
                                  int(offset), xq, wq, self.c_table, faults[0].pits, faults[1].pits,
                                  faults[0].gone, faults[1].gone, faults[0].lost, faults[1].lost)
        cfg = SectorConfig(*(float(x) for x in (
            self.roll_0, self.roll_1, self.reach, self.pitch, self.ra, self.rb, self.estar, self.width,
            self.c_h, self.am, self.af, self.beta, self.gamma, self.h, self.bp, self.gp, self.sigma, self.jn,
            self.theta_lo, self.theta_hi)))
        return self.gears[0].compiled(), self.gears[1].compiled(), contacts, self.table.compiled(), cfg

    def beyond(self, theta_a: float) -> str:
        """Why a run stopped where the driver left the turns its teeth cover (at ``theta_a``)."""
        return (f"the driver had turned {theta_a / self.pitch:.2f} pitches, beyond the "
                f"{self.theta_lo / self.pitch:.2f} to {self.theta_hi / self.pitch:.2f} its teeth cover "
                f"(its speed left {self.speed * 60 / (2 * math.pi):,.0f} rpm by too much)")


#: Fewest periods (revolutions) a faulty run takes: the settled test compares the last two.
FAULTY_PERIODS = 2


def whole_periods(cycles: int, most: int, period: int, default_most: bool) -> tuple[int, int]:
    """A run's cycles and most cycles as whole periods, at least :data:`FAULTY_PERIODS` of
    them where the period is more than a mesh cycle (a faulty pair), and unless the run
    gives its most, room for two more (the first period is the start's transient)."""
    if period == 1:
        return cycles, most
    cycles = max(-(-cycles // period), FAULTY_PERIODS) * period
    most = max(-(-most // period) * period, cycles)
    return cycles, max(most, cycles + 2 * period) if default_most else most


def _block(dp: GearPair, g: int, sense: float, first: int, count: int, mesh_keys: tuple[Any, ...],
           faults: GearFaults | None) -> Any:
    """Gear ``g``'s block (cached per process), with its faults' missing, cracked and chipped
    teeth."""
    gear = dp.gear_a if g == 0 else dp.gear_b
    if faults is None or not (faults.missing or faults.meshed):
        return cached(("block", gear, sense, first, count, *mesh_keys), lambda: gear_block(gear, sense, first, count,
                                                                                          *mesh_keys))
    return cached(("block", gear, sense, first, count, *mesh_keys, faults.missing, faults.meshed),
                  lambda: gear_block(gear, sense, first, count, *mesh_keys, missing=faults.missing,
                                     cracked=cracked_meshes(dp, faults, g, *mesh_keys)))


__all__ = ["FAULTY_PERIODS", "SectorModel", "Start", "faulty_cycles_of", "whole_periods"]

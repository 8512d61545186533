"""The distributed (Hertzian) contact, piece by piece (docs/solver.md, section 11): Hertz's
formulas, the strip quadrature, the strip rows as consistent loads and their compiled
twin, the strip gap of rigid teeth, its curvature compliance, its Jacobian by finite
differences, and the compiled step against the NumPy step."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from spurdyn.contact import hertz
from spurdyn.contact import strip_compiled as strip_c
from spurdyn.contact.search_numpy import FLANK, row_point, sliding_acceleration
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.errors import InputError
from spurdyn.fem.element import edge_weights
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.system import build_system
from spurdyn.settings import RPM, RunSettings
from spurdyn.solvers.paper.dynamics_numpy import (
    blocks, contact_at, jacobian, paper_flanks, rigid_flanks, rot, strip_law,
)
from spurdyn.solvers.paper.step_numpy import PaperMethod, initial_state
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper, pack

from test_contact import bent, rigid, smooth_field

PAIR = paper_pair()


@pytest.fixture(scope="module")
def hertz_system():
    case = RunSettings(speed_a=400.0, speed_b=400.0, torque=PAPER_TORQUE, contact="hertz")
    s = build_system(PAIR, case)
    return s, PaperMethod(s, case)


def test_hertz_strip_of_the_papers_pair_at_the_pitch_point():
    """The issue's figures: at the pitch point under 532.7 N the half-width is about 84 um
    and the peak pressure about 640 MPa; the pressure integrates back to the force."""
    ga, gb = PAIR.gear_a, PAIR.gear_b
    estar = hertz.effective_modulus(ga.material.young, ga.material.poisson,
                                    gb.material.young, gb.material.poisson)
    rho = ga.base_radius * math.tan(ga.pressure_angle)          # 15.2 mm each
    force = 532.7
    b = hertz.half_width(force, rho, rho, estar, ga.face_width)
    p0 = hertz.peak_pressure(force, b, ga.face_width)
    assert b == pytest.approx(84e-6, rel=0.01)
    assert p0 == pytest.approx(640e6, rel=0.01)
    total, _ = quad(lambda xi: p0 * math.sqrt(1.0 - (xi / b) ** 2) * ga.face_width, -b, b)
    assert total == pytest.approx(force, rel=1e-9)
    # b grows as sqrt(F), and no force is no strip
    assert hertz.half_width(4 * force, rho, rho, estar, ga.face_width) == pytest.approx(2 * b)
    assert hertz.half_width(0.0, rho, rho, estar, ga.face_width) == 0.0
    # c_H is the elliptic mean of the curvature separation, b^2 / (8 R*) per newton
    r_star = rho / 2
    assert b**2 / (8 * r_star) / force == pytest.approx(
        hertz.strip_compliance(estar, ga.face_width), rel=1e-12)


def test_strip_quadrature_integrates_the_elliptic_moments():
    """The even moments of (2/pi) sqrt(1 - x^2) are the Catalan numbers over 4^m, exact
    up to the rule's degree 2n - 1 and not beyond."""
    x, w = hertz.strip_quadrature()
    n = hertz.STRIP_POINTS
    for m in range(0, n + 2):
        exact = math.comb(2 * m, m) / (m + 1) / 4**m
        got = np.sum(w * x ** (2 * m))
        if 2 * m <= 2 * n - 1:
            assert got == pytest.approx(exact, rel=1e-13)
        else:
            assert abs(got - exact) > 1e-10
    assert np.sum(w * x) == pytest.approx(0.0, abs=1e-15)     # symmetric


@pytest.mark.parametrize("where", ["inside an element", "across an element edge"])
def test_strip_rows_are_the_consistent_loads_of_the_elliptic_pressure(hertz_system, where):
    """``N_bar = int N(t(xi)) p(xi) dxi / F``, integrated here piecewise with SciPy."""
    s, _ = hertz_system
    f = s.gears[0].flank
    t_c = 7.5 if where == "inside an element" else 8.0 + 1e-3
    b = 60e-6
    nodes, w, delta = strip_rows(f, t_c, b)
    assert w.sum() == pytest.approx(1.0, abs=1e-14)
    r_c = f.r0 + (f.r_tip - f.r0) * t_c / f.ny

    def t_of(xi: float) -> float:
        r = math.sqrt(r_c**2 + 2 * f.base_radius * xi)
        return (r - f.r0) / (f.r_tip - f.r0) * f.ny

    want = np.zeros(f.side_nodes.size)
    edges = [xi for xi in np.linspace(-b, b, 2001)
             if abs(t_of(xi) - round(t_of(xi))) < 1e-3 * (f.ny / (f.r_tip - f.r0)) * 1e-6]
    for j in range(f.side_nodes.size):
        def integrand(xi: float, j: int = j) -> float:
            t = t_of(xi)
            row = min(int(math.floor(t)), f.ny - 1)
            k = j - 2 * row
            if not 0 <= k <= 2:
                return 0.0
            return edge_weights(2 * (t - row) - 1)[k] * 2 / (math.pi * b) * math.sqrt(1 - (xi / b) ** 2)
        want[j], _ = quad(integrand, -b, b, points=edges or None, limit=200)
    got = np.zeros(f.side_nodes.size)
    pos = {int(n): i for i, n in enumerate(f.side_nodes)}
    for n, wn in zip(nodes, w):
        got[pos[int(n)]] += wn
    # Within one element edge the rule is exact; across an edge the integrand has a kink
    # and the 12-point rule carries a small error.
    tol = 1e-12 if where == "inside an element" else 2e-3
    assert np.abs(got - want).max() < tol
    # delta_bar: for a rigid rotation the virtual point is the exact involute at the centre
    assert np.allclose(w @ f.side_Y[np.searchsorted(f.side_nodes, nodes)] + delta, f.exact(t_c),
                       rtol=0, atol=1e-15)


def test_zero_half_width_gives_the_point_contacts_rows(hertz_system):
    s, _ = hertz_system
    f = s.gears[1].flank
    for t in (3.2, 9.0, 13.99):
        nodes, w, d = strip_rows(f, t, 0.0)
        n0, w0, _ = f.locate(t)
        assert np.array_equal(nodes, n0) and np.array_equal(w, w0)
        assert np.array_equal(d, f.delta(t))
    # and the rows are continuous as b -> 0
    nodes, w, _ = strip_rows(f, 9.3, 1e-12)
    n0, w0, _ = f.locate(9.3)
    assert np.array_equal(nodes, n0) and np.abs(w - w0).max() < 1e-9


@pytest.mark.parametrize("t_c,b", [(5.3, 40e-6), (8.0005, 150e-6), (12.0, 400e-6), (13.9, 300e-6)])
def test_compiled_strip_rows_are_the_numpy_ones(hertz_system, t_c, b):
    s, _ = hertz_system
    case = RunSettings(speed_a=400.0, speed_b=400.0, torque=PAPER_TORQUE, contact="hertz")
    P = pack(s, case)
    na = s.gears[0].mesh.n_nodes
    for g in range(2):
        f = s.gears[g].flank
        nodes, w, d = strip_rows(f, t_c, b)
        ns = 2 * f.ny + 1
        cn = np.zeros(2 * ns, np.int64)
        cw = np.zeros(2 * ns)
        dx, dy, fits = strip_c.strip_rows(P, np.int64(g), t_c, b, cn, cw, np.int64(g * ns), ns)
        assert fits
        off = g * ns
        k = nodes.size
        assert np.array_equal(cn[off:off + k], nodes + g * na)
        assert np.abs(cw[off:off + k] - w).max() < 1e-15
        assert np.all(cw[off + k:off + ns] == 0.0)
        assert abs(dx - d[0]) < 1e-17 and abs(dy - d[1]) < 1e-17
    # too few slots: refused, not truncated
    cn, cw = np.zeros(6, np.int64), np.zeros(6)
    assert not strip_c.strip_rows(P, np.int64(0), 12.0, 400e-6, cn, cw, np.int64(0), np.int64(3))[2]


def test_strip_gap_of_rigid_conjugate_teeth_is_zero_under_load(hertz_system):
    """The strip gap is the rigid involutes' gap at the centre plus the averaged elastic
    displacement: rigid conjugate teeth keep it at round-off whatever the strip."""
    s, ref = hertz_system
    guess = (s.gears[0].flank.t0 + 0.5, s.gears[1].flank.t1)
    worst, widths = 0.0, []
    for d in np.linspace(0.02, PAIR.theta_s * 0.95, 9):
        u, _, _ = rigid(s, (d, d))
        c = ref.contact_at(np.array([d, d]), u, guess, 2000.0)
        guess = (c.alpha, c.beta)
        if c.mode == FLANK:
            widths.append(c.half_width)
            worst = max(worst, abs(c.s))
    assert min(widths) > 50e-6 and worst < 1e-14


def test_the_rigid_surfaces_part_by_c_h_times_the_force_over_the_strip(hertz_system):
    """Averaged with the strip's weights, the exact involutes part from the centre's gap
    by b^2 / (8 R*) = c_H F (docs/solver.md, section 11)."""
    s, ref = hertz_system
    fa, fb = s.gears[0].flank, s.gears[1].flank
    estar, face = strip_law(s)
    c_h = hertz.strip_compliance(estar, face)
    theta = np.array([0.18, 0.18])
    u, _, _ = rigid(s, theta)
    c = ref.contact_at(theta, u, (7.0, 7.0), 532.7)
    x, wq = hertz.strip_quadrature()
    ra = np.array([[math.cos(-theta[0]), -math.sin(-theta[0])], [math.sin(-theta[0]), math.cos(-theta[0])]])
    rb = np.array([[math.cos(theta[1]), -math.sin(theta[1])], [math.sin(theta[1]), math.cos(theta[1])]])
    ca, cb = s.gears[0].centre, s.gears[1].centre
    ta = hertz.strip_coordinates(c.alpha, c.half_width, fa.r0, fa.r_tip, fa.ny, fa.base_radius, x)
    tb = hertz.strip_coordinates(c.beta, c.half_width, fb.r0, fb.r_tip, fb.ny, fb.base_radius, x)
    mean_a = sum(wk * (ca + ra @ fa.exact(t)) for wk, t in zip(wq, ta))
    mean_b = sum(wk * (cb + rb @ fb.exact(t)) for wk, t in zip(wq, tb))
    centre_gap = c.normal @ ((ca + ra @ fa.exact(c.alpha)) - (cb + rb @ fb.exact(c.beta)))
    separation = centre_gap - c.normal @ (mean_a - mean_b)
    assert separation == pytest.approx(c_h * 532.7, rel=0.02)


def test_strip_jacobian_by_finite_differences(hertz_system):
    """ds_bar/du along smooth displacements equals the strip's contact row of G."""
    s, ref = hertz_system
    rng = np.random.default_rng(3)
    theta = np.array([0.1, 0.1])
    u0, y = bent(s, theta)
    c = ref.contact_at(theta, u0, (5.0, 11.0), 3000.0)
    assert c.half_width > 100e-6 and c.nodes_a.size >= 3
    g = jacobian(s, theta, c)[-1, 2:]
    for _ in range(3):
        du = smooth_field(y, rng)
        eps = 1e-9
        sp = ref.contact_at(theta, u0 + eps * du, (c.alpha, c.beta), 3000.0).s
        sm = ref.contact_at(theta, u0 - eps * du, (c.alpha, c.beta), 3000.0).s
        assert (sp - sm) / (2 * eps) == pytest.approx(g @ du, rel=2e-5, abs=1e-9)


@pytest.mark.parametrize("turn", [0.05, 0.12, 0.2])
def test_the_strips_row_carries_its_pairs_roll_with_the_disks(hertz_system, turn):
    """d s_bar / d theta at fixed u equals the contact row's disk entries (docs/solver.md
    11.3): the pair on the rigid flanks rolls with the disks and the bent flanks' slope
    under the strip changes the gap it holds. Without the entries the row says zero."""
    s, ref = hertz_system
    theta = np.array([turn, turn])
    u0, _ = bent(s, theta)
    c = ref.contact_at(theta, u0, (5.0, 11.0), 3000.0)
    assert c.mode == FLANK and c.half_width > 100e-6
    row = jacobian(s, theta, c)[-1, :2]
    assert np.all(np.abs(row) > 1e-8)            # m/rad: the roll of ~1e-3 slopes
    fa, fb = paper_flanks(s)
    xa, xb = (gb.X + ub.reshape(-1, 2) for gb, ub in zip(s.gears, blocks(s, u0)))

    def gap(th):
        """The strip's gap at the pair found at ``th``, its half-width held (as a step
        holds it)."""
        p = ref.contact_at(th, u0, (c.alpha, c.beta), 3000.0)
        ra, rb = (rot(gb.sense * t) for gb, t in zip(s.gears, th))
        return p.normal @ (row_point(fa, p.alpha, c.half_width, xa, ra)
                           - row_point(fb, p.beta, c.half_width, xb, rb))

    for g in range(2):
        eps = 1e-5          # rad: the gap's round-off (1e-17 m) is then 1e-6 of the entries
        d = np.zeros(2)
        d[g] = eps
        # measured within 3e-4 (not yet explained: not the round-off, which is 1e-6 here)
        assert (gap(theta + d) - gap(theta - d)) / (2 * eps) == pytest.approx(row[g], rel=1e-3)


def _turning_bent(system, theta, omega, alpha, bend):
    """Displacements, velocities and accelerations of teeth bent by ``bend`` (nodal, in
    each disk's frame) and turning rigidly with their disks."""
    n = system.n_u
    u, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    jz = np.array([[0.0, -1.0], [1.0, 0.0]])
    for g, (gb, ub, vb, ab, wb) in enumerate(zip(system.gears, *(blocks(system, z) for z in (u, v, a, bend)))):
        y = gb.Y.reshape(-1, 2)
        ry = (y + wb.reshape(-1, 2)) @ rot(gb.sense * theta[g]).T
        ub[:] = (ry - y).ravel()
        vb[:] = (gb.sense * omega[g] * ry @ jz.T).ravel()
        ab[:] = (gb.sense * alpha[g] * ry @ jz.T - omega[g] ** 2 * ry).ravel()
    return u, v, a


def test_the_strip_sits_on_the_rigid_flanks_and_its_sliding_terms_follow_its_gap(hertz_system):
    """The strip's pair is the rigidly turned flanks' one whatever the deformation, and for
    bent teeth turning and accelerating, the relative normal acceleration with the rigid
    pair's rates (``rates_from``) is the second time derivative of the strip's gap
    (docs/solver.md, section 11.2). Left out by design: ``alpha_ddot n . P'`` of the bent
    flank and the normal's turning on a relieved flank (none here)."""
    s, ref = hertz_system
    th0 = np.array([0.12, 0.12])
    om, al = np.array([2000.0, 2000.0]), np.array([0.0, 5e4])
    y = np.concatenate([g.Y for g in s.gears]).reshape(-1, 2)
    bend = 1e-4 * np.column_stack([y[:, 1] ** 2, y[:, 0] * y[:, 1]]).ravel()   # ~0.2 um
    load = 2000.0

    def strip_at(t):
        th = th0 + om * t + 0.5 * al * t * t
        return ref.contact_at(th, _turning_bent(s, th, om + al * t, al, bend)[0], (5.0, 10.0), load)

    c0 = strip_at(0.0)
    rigid_pair = contact_at(s, th0, rigid(s, th0)[0], (5.0, 10.0))
    assert c0.mode == FLANK and c0.half_width > 50e-6
    assert (c0.alpha, c0.beta) == pytest.approx((rigid_pair.alpha, rigid_pair.beta), abs=1e-12)
    bent_pair = contact_at(s, th0, _turning_bent(s, th0, om, al, bend)[0], (5.0, 10.0))  # no law
    assert abs(bent_pair.alpha - c0.alpha) > 1e-5       # the bend moves the deformed pair (3e-4)
    dt = 2e-7
    fd = (strip_at(dt).s - 2 * c0.s + strip_at(-dt).s) / dt**2
    u, v, a = _turning_bent(s, th0, om, al, bend)
    ua, ub = blocks(s, u)
    va, vb = blocks(s, v)
    ra, rb = (rot(g.sense * t) for g, t in zip(s.gears, th0))
    args = (s.gears[0].flank, s.gears[1].flank, s.gears[0].X + ua.reshape(-1, 2),
            s.gears[1].X + ub.reshape(-1, 2), ra, rb, va.reshape(-1, 2), vb.reshape(-1, 2),
            *ref.velocity_mats(th0, om), c0)
    extra, ad, bd = sliding_acceleration(*args, rates_from=tuple(rigid_flanks(s, th0, om)))
    s_tilde = ref.normal_of(c0, a, ref.acceleration_mats(th0, om, al)) + extra
    assert abs(extra) > abs(s_tilde)
    assert abs(s_tilde - fd) < 2e-5 * abs(extra)
    # and the pair moves at the rigid rates
    c1 = strip_at(dt)
    assert (c1.alpha - c0.alpha) / dt == pytest.approx(ad, rel=1e-3)
    assert (c1.beta - c0.beta) / dt == pytest.approx(bd, rel=1e-3)


@pytest.mark.slow
def test_compiled_and_numpy_hertz_steps_agree():
    """The two backends of the distributed contact, step by step at 20,000 rpm, on 2 x 8
    teeth meshes (the reference's steps cost as the DOFs; the differences are as small a part
    of the tolerances as on the default 4 x 14)."""
    case = RunSettings(speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE,
                       contact="hertz", nx=2, ny=8)
    system = build_system(PAIR, case)
    fast, ref = CompiledStepper(system, case), PaperMethod(system, case)
    st = initial_state(system, case)
    worst = np.zeros(5)
    peak, width = 0.0, 0.0
    for i in range(300):
        assert fast.step() == 0
        st, rep = ref.step(st, i + 1)
        assert rep.status == 0
        S = fast.S
        peak, width = max(peak, -st.x[-1]), max(width, st.contact.half_width)
        worst = np.maximum(worst, [np.abs(S.u - st.u).max(), np.abs(S.v - st.v).max(),
                                   abs(S.x[-1] - st.x[-1]), abs(S.cpar[5] - st.contact.half_width),
                                   np.abs(S.gth - np.array(st.contact.theta_row)).max()])
    assert peak > 20.0 and width > 10e-6
    assert worst[0] < 1e-2 * case.tol_disp
    assert worst[1] < 1e-2 * case.tol_vel
    assert worst[2] < 1e-3
    assert worst[3] < 1e-12
    assert worst[4] < 1e-11          # m/rad, of ~1.5e-7: the pair's roll in the row (11.3)


def test_contact_choices_and_refusals():
    base = dict(speed_a=400.0, speed_b=400.0, torque=1.0)
    assert RunSettings(**base).contact in ("point", "hertz")
    with pytest.raises(InputError, match="contact"):
        RunSettings(**base, contact="line")
    # the point contact's stall fallback "pinned" was retired: a case asking for it is told why
    with pytest.raises(InputError, match="retired.*hertz"):
        RunSettings(**base, method="pinned")


def test_static_point_stiffness_is_the_models_and_the_strip_is_softer_by_its_compliances():
    """``statics.static_stiffness`` with the point is ``model.stiffness``'s pitch-point
    figure; with the strip, 1 / (c_A + c_B + c_H) with c_H the curvature compliance."""
    from spurdyn.model.stiffness import pitch_point_stiffness
    from spurdyn.model.tooth import build_tooth
    from spurdyn.solvers.paper.statics import static_stiffness

    s = build_system(PAIR, RunSettings(speed_a=1.0, speed_b=1.0, torque=PAPER_TORQUE))
    force = PAPER_TORQUE / PAIR.gear_a.base_radius
    point = static_stiffness(s, PAIR.pitch_roll_a, force, "point")
    teeth = build_tooth(PAIR.gear_a), build_tooth(PAIR.gear_b)
    assert point.stiffness == pytest.approx(pitch_point_stiffness(PAIR, *teeth), rel=1e-6)
    strip = static_stiffness(s, PAIR.pitch_roll_a, force, "hertz")
    assert strip.half_width == pytest.approx(84e-6, rel=0.01)
    assert strip.compliance_strip == pytest.approx(hertz.strip_compliance(*strip_law(s)))
    assert strip.stiffness == pytest.approx(
        1 / (strip.compliance_a + strip.compliance_b + strip.compliance_strip), rel=1e-12)
    assert strip.stiffness < point.stiffness


def test_info_reports_the_stiffness_of_the_contact_asked_for(capsys):
    from spurdyn.cli.main import main

    def info(*extra):
        assert main(["info", "paper", "--json", *extra]) == 0
        return json.loads(capsys.readouterr().out)

    point, strip = info(), info("--contact", "hertz")
    assert point["contact"] == "point" and strip["contact"] == "hertz"
    assert strip["contact_force_N"] == pytest.approx(PAPER_TORQUE / PAIR.gear_a.base_radius)
    assert strip["pair_stiffness_pitch_N_per_m"] < point["pair_stiffness_pitch_N_per_m"]
    heavier = info("--contact", "hertz", "--torque", str(4 * PAPER_TORQUE))
    # a wider strip spreads the load: the pair is stiffer under more load
    assert heavier["strip_half_width_pitch_m"] == pytest.approx(2 * strip["strip_half_width_pitch_m"])
    assert heavier["pair_stiffness_pitch_N_per_m"] > strip["pair_stiffness_pitch_N_per_m"]


def test_case_files_default_to_the_strip_and_presets_to_the_point(tmp_path):
    from spurdyn.case import resolve_cases

    examples = Path(__file__).resolve().parents[1] / "examples"
    assert resolve_cases("paper-fig8")[0].run.contact == "point"
    assert resolve_cases(str(examples / "pinion_gear.toml"))[0].run.contact == "hertz"
    assert resolve_cases("paper-fig8", {"run.contact": "hertz"})[0].run.contact == "hertz"
    text = (examples / "pinion_gear.toml").read_text()
    pinned = tmp_path / "pinned.toml"
    pinned.write_text(text.replace("[run]\n", '[run]\nmethod = "pinned"\n'))
    with pytest.raises(InputError, match="run.method.*retired"):
        resolve_cases(str(pinned))


def test_the_lumped_model_takes_the_strips_stiffness():
    from spurdyn.lumped import mesh_stiffness_table
    from spurdyn.lumped.sources import hertz_table as _hertz_table

    case = RunSettings(speed_a=400.0, speed_b=400.0, torque=PAPER_TORQUE)
    strip = _hertz_table(PAIR, case)
    point = mesh_stiffness_table(PAIR, case.nx, case.ny)
    assert np.allclose(strip.roll_a, point.roll_a)
    ratio = strip.stiffness / point.stiffness
    # softer along the path by the strip's compliance; at the ends of the path (a tip) a
    # strip spreads the load that a point puts on the tip's last element, and is stiffer
    assert np.all(ratio[1:-1] < 1.0) and np.all(ratio > 0.9)
    assert ratio[0] > ratio[1] and ratio[-1] > ratio[-2]


def test_the_lumped_strip_table_does_not_depend_on_which_equal_pair_built_the_system():
    """The system cache may hand back a system built from an equal pair object: the
    table must still run along A's roll (a B-driving mapping applied to an A-driving pair
    would put the stiffness at the wrong roll angles)."""
    from dataclasses import replace as dc_replace

    from spurdyn.model.system import _kept_system, system_for
    from spurdyn.lumped.sources import hertz_table as _hertz_table

    from spurdyn.case import resolve_cases

    examples = Path(__file__).resolve().parents[1] / "examples"
    pinion = resolve_cases(str(examples / "pinion_gear.toml"))[0]   # 20 / 40 teeth
    pair, case = pinion.pair, pinion.run
    twin = dc_replace(pair)
    assert twin == pair and twin is not pair
    _kept_system.cache_clear()
    system_for(twin, case.nx, case.ny, case.n_spline)   # the cache now holds twin's system
    assert system_for(pair, case.nx, case.ny, case.n_spline).pair is twin
    table = _hertz_table(pair, case)
    assert table.roll_a[0] == pytest.approx(pair.start_roll_a)
    assert table.roll_a[-1] == pytest.approx(pair.end_roll_a)


@pytest.mark.slow
def test_a_graded_mesh_brings_the_strip_stiffness_nearer_its_fine_mesh_limit():
    """Thin outline columns resolve the strip's near field: the pitch-point stiffness of
    12 x 40 graded 6 lies nearer that of 24 x 80 (graded alike) than the even 12 x 40 lies
    to the even 24 x 80, and the graded meshes are the more compliant (nearer the limit
    approached from above)."""
    from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
    from spurdyn.model.system import system_for
    from spurdyn.solvers.paper.statics import static_stiffness

    pair = paper_pair()
    force = PAPER_TORQUE / pair.gear_a.base_radius

    def k(nx, ny, grading):
        s = system_for(pair, nx, ny, 61, grading)
        return static_stiffness(s, pair.pitch_roll_a, force, "hertz").stiffness

    even = k(12, 40, 1.0) / k(24, 80, 1.0) - 1.0
    graded = k(12, 40, 6.0) / k(24, 80, 6.0) - 1.0
    assert 0.0 < graded < 0.75 * even
    assert k(12, 40, 6.0) < k(12, 40, 1.0)


def test_the_grading_of_a_case_is_kept_in_its_stored_case():
    from spurdyn.case import case_from_dict, case_to_dict, resolve_cases

    with pytest.raises(InputError, match=r"mesh.grading: dt 3e-08 s is above .* 4x14 tooth "
                       r"mesh graded 4; .* or less grading"):
        resolve_cases("paper-fig8", {"mesh.grading": 4.0})     # the preset's dt is too large
    case = resolve_cases("paper-fig8", {"mesh.grading": 4.0, "run.dt": 2e-8,
                                        "run.angle_deg": 0.1})[0]
    assert case.run.grading == 4.0
    again = case_from_dict(case_to_dict(case), check_step=False)
    assert again.run.grading == 4.0 and again.run == case.run.with_(name=again.run.name)

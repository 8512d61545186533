"""The sector model's compiled pieces that both compiled loops read (the implicit loop of
:mod:`spurdyn.solvers.sector.step_compiled` and the RK4 reference's of
:mod:`spurdyn.solvers.sector.rk4_compiled`): the rigid gap's table, a flank's unit strip
load, the bodies' free accelerations, the pairs' contact rows and residual compliance, the
mesh damper's coefficient, and the complementarity problem by active sets.

Each has its NumPy twin: :meth:`~spurdyn.sector.system.GapTable.at`,
:meth:`~spurdyn.sector.system.GearBlock.flank_loads`,
:meth:`~spurdyn.sector.bodies.ModalBody.forces` and ``solve``,
:meth:`~spurdyn.sector.model.SectorModel.rows_at` with the bodies' ``rows`` and
``residual``, :func:`~spurdyn.sector.damper.damper_at`, and
:func:`~spurdyn.sector.lcp.lcp`. The gears are :data:`~spurdyn.sector.packs.ModalGear`
packs, the table a :data:`~spurdyn.sector.packs.GapArrays`, the contacts a
:data:`~spurdyn.sector.packs.SectorContacts` and the run's scalars a
:data:`~spurdyn.sector.packs.SectorConfig`.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.contact.search_compiled import edge_shape
from spurdyn.contact.strip_compiled import hertz_half_width, involute_curvature
from spurdyn.jit import njit
from spurdyn.sector.lcp import BLOCK_TRIES, PIVOTS

#: Counts of pairs near the path whose active sets the loops order once (two to four occur).
ORDERS = 6


@njit
def table_at(table, x):
    """The rigid gap's table at roll ``x``: ``(g, dg/drho, r_a, r_b)`` (twin of ``GapTable.at``)."""
    t_rho = table.rho
    n = t_rho.size
    i = np.searchsorted(t_rho, x, side="right") - 1
    i = min(max(i, 0), n - 2)
    if t_rho[i + 1] == t_rho[i]:
        i += 1
    x0 = t_rho[i]
    h = t_rho[i + 1] - x0
    u = (x - x0) / h
    g0, g1 = table.gap[i], table.gap[i + 1]
    d0, d1 = table.slope[i] * h, table.slope[i + 1] * h
    u2 = u * u
    u3 = u2 * u
    gap = (2 * u3 - 3 * u2 + 1) * g0 + (u3 - 2 * u2 + u) * d0 + (-2 * u3 + 3 * u2) * g1 + (u3 - u2) * d1
    slope = ((6 * u2 - 6 * u) * g0 + (3 * u2 - 4 * u + 1) * d0 + (-6 * u2 + 6 * u) * g1
             + (3 * u2 - 2 * u) * d1) / h
    r_a = table.r_a[i] + u * (table.r_a[i + 1] - table.r_a[i])
    r_b = table.r_b[i] + u * (table.r_b[i + 1] - table.r_b[i])
    return gap, slope, r_a, r_b


@njit
def flank_load(geo, r, b, xq, wq, out):
    """The unit strip load at involute radius ``r``, half-width ``b``, on a flank in tooth 0's
    frame (twin of ``GearBlock.flank_loads``), into ``out`` (``2 (2 ny + 1)``)."""
    r0, r_tip, ny_f, rbase, hab = geo[0], geo[1], geo[2], geo[3], geo[4]
    ny = int(ny_f)
    slope = (r_tip - r0) / ny
    out[:] = 0.0
    for k in range(xq.size):
        rk = math.sqrt(max(r * r + 2.0 * rbase * b * xq[k], 0.0))
        t = min(max((rk - r0) / slope, 0.0), float(ny))
        row = min(int(math.floor(t)), ny - 1)
        s0, s1, s2 = edge_shape(2.0 * (t - row) - 1.0)
        out[2 * (2 * row)] += s0 * wq[k]
        out[2 * (2 * row + 1)] += s1 * wq[k]
        out[2 * (2 * row + 2)] += s2 * wq[k]
    # the mating flank pushes into the tooth, against the outward normal
    alpha = math.acos(min(max(rbase / r, -1.0), 1.0))
    chi = hab - math.tan(alpha)
    nx, nyy = math.cos(chi), -math.sin(chi)
    for j in range(2 * ny + 1):
        w = out[2 * j]
        out[2 * j] = -w * nx
        out[2 * j + 1] = -w * nyy


@njit
def modal_free(tq0, tq1, q, v, gear0, gear1):
    """The bodies' accelerations without the contacts' forces: the hubs' torques ``tq0``,
    ``tq1`` less each mode's damping and stiffness at ``(q, v)``, through each gear's
    :func:`arrow` (``S^-1`` of the implicit loop, ``M^-1`` of the RK4 reference)."""
    na = gear0.omega2.size + 1
    n = na + gear1.omega2.size + 1
    r = np.zeros(n)
    r[0] = tq0
    r[na] = tq1
    for j in range(gear0.omega2.size):
        r[1 + j] -= gear0.damp[j] * v[1 + j] + gear0.omega2[j] * q[1 + j]
    for j in range(gear1.omega2.size):
        r[na + 1 + j] -= gear1.damp[j] * v[na + 1 + j] + gear1.omega2[j] * q[na + 1 + j]
    out = np.empty(n)
    out[:na] = arrow(gear0, r[:na])
    out[na:] = arrow(gear1, r[na:])
    return out


@njit
def arrow(gear, x):
    """``S^-1 x`` of the gear's arrow ``S`` (:data:`~spurdyn.sector.packs.ModalGear`; twin
    of :func:`spurdyn.sector.bodies.arrow_solve`): O(n), not a dense inverse's O(n^2)."""
    u, dinv = gear.u, gear.dinv
    m = u.size
    hub = x[0]
    for j in range(m):
        hub -= u[j] * x[1 + j]
    hub /= gear.schur
    y = np.empty(m + 1)
    y[0] = hub
    for j in range(m):
        y[1 + j] = dinv[j] * x[1 + j] - u[j] * hub
    return y


@njit
def hub_column(gear):
    """``z = S^-1 e_0``: the gear's response to a unit hub torque."""
    e = np.zeros(gear.u.size + 1)
    e[0] = 1.0
    return arrow(gear, e)


@njit
def damper_coefficient(c_table, pitch, theta):
    """The mesh damper's coefficient at the driver's turn ``theta`` (twin of ``damper.damper_at``)."""
    n_damp = c_table.size - 1
    x_d = (theta % pitch) / pitch * n_damp
    i_d = min(int(x_d), n_damp - 1)
    f_d = x_d - i_d
    return c_table[i_d] * (1.0 - f_d) + c_table[i_d + 1] * f_d


@njit
def contact_rows(theta, widths, gear0, gear1, con, table, cfg):
    """The contacts near their paths at the driver's turn ``theta``: ``(on, const, coef0,
    coef1, rows0, rows1, res)``, their indices in the run's contacts, the constant parts of
    their gaps, per gear the rows' hub coefficients and modal rows, and the bodies' residual
    compliance between their loads (``b_i^T R b_j``); the strips' half-widths those of the
    forces ``widths`` (twin of ``SectorModel.rows_at`` with the bodies' ``residual``). A back
    flank's roll runs backwards (``system.back_roll_sum``). No contact: ``on`` empty. A
    contact in a pit over part of the face width is two rows (:func:`rows_and_loads`), here
    entering it (the RK4 reference refuses such pits)."""
    return rows_and_loads(theta, widths, np.full(widths.size, -1.0), gear0, gear1, con, table, cfg)[0]


@njit
def rows_and_loads(theta, widths, pit, gear0, gear1, con, table, cfg):
    """:func:`contact_rows` and the pairs' unit loads it took, per gear ``(loads, idx, cnt,
    at)`` (the loads in tooth 0's frame, their nonzero columns and the body teeth), the
    flanks ``sd``, and per row its kind and force of the step before (:func:`split_rows`):
    ``(rows, loads0, loads1, sd, (kind, held))``. A contact whose flank is in a pit over part
    of the face width is two rows (docs/faults.md, section 8): ``on`` names its contact twice,
    the intact strip's row and then the pit's, each with the strip compliance of its share
    ``s`` of the width, ``c_H / s`` (its part beyond ``c_H`` on ``res``'s diagonal), the
    Hertz half-width of its own force per width and the pit's row its gap ``+ depth``;
    ``pit`` the pit strips' forces of the step before (:func:`split_rows`)."""
    teeth, sides = con.teeth, con.sides
    nt = teeth.size
    on_all = np.empty(nt, np.int64)
    p = 0
    for i in range(nt):
        roll = cfg.roll_0 + theta + teeth[i] * cfg.pitch
        if sides[i]:
            roll = cfg.sigma - roll
        k = teeth[i] + con.offset
        k0, k1 = (k - gear0.first) % gear0.count, (-k + sides[i] - gear1.first) % gear1.count
        # a missing tooth, or a chipped flank beyond its cut (twin: SectorModel.made, lost)
        gone = (con.gone0[k0] != 0 or con.gone1[k1] != 0
                or con.lost0[k0, sides[i], 0] < roll < con.lost0[k0, sides[i], 1]
                or con.lost1[k1, sides[i], 0] < roll < con.lost1[k1, sides[i], 1])
        if roll >= cfg.roll_0 - cfg.reach and roll <= cfg.roll_1 + cfg.reach and not gone:
            on_all[p] = i
            p += 1
    near = on_all[:p].copy()
    shares, depths = _pit_shares(theta, near, gear0, gear1, con, cfg)
    on, kind, share, extra, held = split_rows(near, shares, depths, widths, pit)
    p = on.size
    nf = gear0.modes.shape[2]
    if p == 0:      # no pair near the path: no rows (and no products of empty arrays)
        none = (np.empty((0, nf)), np.empty((0, nf), np.int64), np.empty(0, np.int64), np.empty(0, np.int64))
        return ((on, np.empty(0), np.empty(0), np.empty(0), np.empty((0, gear0.omega2.size)),
                 np.empty((0, gear1.omega2.size)), np.zeros((0, 0))), none, none, np.empty(0, np.int64),
                (kind, held))
    const = np.empty(p)
    coef0 = np.empty(p)
    coef1 = np.empty(p)
    at0 = np.empty(p, np.int64)
    at1 = np.empty(p, np.int64)
    sd = np.empty(p, np.int64)
    loads0 = np.empty((p, nf))
    loads1 = np.empty((p, nf))
    for a in range(p):
        i = on[a]
        sd[a] = sides[i]
        # d roll / d theta_A: +1 on a drive flank, -1 on a back flank
        sgn = -1.0 if sd[a] else 1.0
        rho = cfg.roll_0 + theta + teeth[i] * cfg.pitch
        if sd[a]:
            rho = cfg.sigma - rho
        g0, slope, r_a, r_b = table_at(table, rho)
        hw = hertz_half_width(held[a], involute_curvature(r_a, gear0.geo[3]),
                              involute_curvature(r_b, gear1.geo[3]), cfg.estar, cfg.width * share[a])
        const[a] = g0 - sgn * slope * theta + (cfg.jn if sd[a] else 0.0)
        coef0[a] = sgn * (slope - cfg.ra)
        coef1[a] = sgn * cfg.rb
        k = teeth[i] + con.offset
        at0[a] = (k - gear0.first) % gear0.count
        at1[a] = (-k + sd[a] - gear1.first) % gear1.count
        const[a] += pit_gap(con.pits0[at0[a], sd[a]], rho) + pit_gap(con.pits1[at1[a], sd[a]], rho) + extra[a]
        flank_load(gear0.geo, r_a, hw, con.xq, con.wq, loads0[a])
        flank_load(gear1.geo, r_b, hw, con.xq, con.wq, loads1[a])
    # a strip's load touches a few of the flank's nodes: the products run over those alone
    idx0, cnt0 = _nonzeros(loads0)
    idx1, cnt1 = _nonzeros(loads1)
    rows0 = _modal_rows(loads0, idx0, cnt0, gear0.modes, at0, sd)
    rows1 = _modal_rows(loads1, idx1, cnt1, gear1.modes, at1, sd)
    res = (_static_pairs(loads0, idx0, cnt0, gear0.flex, at0, sd, gear0.count, gear0.ring)
           + _static_pairs(loads1, idx1, cnt1, gear1.flex, at1, sd, gear1.count, gear1.ring))
    res -= (rows0 / gear0.omega2) @ rows0.T + (rows1 / gear1.omega2) @ rows1.T
    for a in range(p):
        if kind[a]:     # a strip's compliance c_H / s beyond the c_H every row has
            res[a, a] += cfg.c_h / share[a] - cfg.c_h
    return ((on, const, coef0, coef1, rows0, rows1, res), (loads0, idx0, cnt0, at0), (loads1, idx1, cnt1, at1),
            sd, (kind, held))


@njit
def _pit_shares(theta, near, gear0, gear1, con, cfg):
    """Per contact ``near`` the share of the face width a pit over part of it covers at its
    roll (0: none there) and the pit's depth: ``(shares, depths)`` (one gear's pits at most
    are partial, :func:`~spurdyn.sector.fault_bodies.gear_faults`)."""
    p = near.size
    shares, depths = np.zeros(p), np.zeros(p)
    for a in range(p):
        i = near[a]
        sd = con.sides[i]
        rho = cfg.roll_0 + theta + con.teeth[i] * cfg.pitch
        if sd:
            rho = cfg.sigma - rho
        k = con.teeth[i] + con.offset
        at0, at1 = (k - gear0.first) % gear0.count, (-k + sd - gear1.first) % gear1.count
        for pit in (con.pits0[at0, sd], con.pits1[at1, sd]):
            if 0.0 < pit[3] < 1.0 and pit[0] <= rho <= pit[1]:
                shares[a], depths[a] = pit[3], pit[2]
    return shares, depths


@njit
def split_rows(near, shares, depths, last, pit):
    """The step's rows of the contacts ``near`` (docs/faults.md, section 8): one a contact,
    two where a pit over the share ``shares[a]`` of the face width (0: none) splits it, the
    intact strip's and then the pit's. Per row ``(on, kind, share, extra, held)``: its
    contact, kind (0 whole, 1 the intact strip, 2 the pit's), share of the width, extra gap
    (the pit's ``depths[a]``) and force of the step before: the contact's ``last``, split by
    ``pit`` (the pit strip's force, -1 where the contact was whole) or, as it enters the
    pit, in proportion to the shares (equal forces per width, a whole contact's)."""
    p = near.size
    n = p
    for a in range(p):
        if shares[a] > 0.0:
            n += 1
    on = np.empty(n, np.int64)
    kind = np.zeros(n, np.int64)
    share, extra, held = np.ones(n), np.zeros(n), np.empty(n)
    r = 0
    for a in range(p):
        i = near[a]
        on[r] = i
        held[r] = last[i]
        w = shares[a]
        if w > 0.0:
            was = pit.size > 0 and pit[i] >= 0.0
            held[r] = last[i] - pit[i] if was else (1.0 - w) * last[i]
            kind[r], share[r] = 1, 1.0 - w
            r += 1
            on[r], kind[r], share[r], extra[r] = i, 2, w, depths[a]
            held[r] = pit[i] if was else w * last[i]
        r += 1
    return on, kind, share, extra, held


@njit
def _nonzeros(loads):
    """Per row of ``loads`` ``(p, f)`` the columns that are not zero: ``(idx, count)``."""
    p, nf = loads.shape
    idx = np.empty((p, nf), np.int64)
    cnt = np.zeros(p, np.int64)
    for a in range(p):
        for i in range(nf):
            if loads[a, i] != 0.0:
                idx[a, cnt[a]] = i
                cnt[a] += 1
    return idx, cnt


@njit
def _modal_rows(loads, idx, cnt, modes, at, sd):
    """``(p, m)`` the pairs' modal rows ``Phi_k^T b``: each load on its tooth ``at`` and
    flank ``sd`` (``modes`` of :data:`~spurdyn.sector.packs.ModalGear`), over its nonzeros."""
    p, m = loads.shape[0], modes.shape[3]
    rows = np.zeros((p, m))
    for a in range(p):
        md = modes[at[a], sd[a]]
        for t in range(cnt[a]):
            i = idx[a, t]
            w = loads[a, i]
            for j in range(m):
                rows[a, j] += w * md[i, j]
    return rows


@njit
def pit_gap(pit, rho):
    """The extra gap (m) of a flank's pit ``(lo, hi, depth, width)`` across the face width
    at the contact's roll ``rho`` (twin of ``SectorModel.pit_gaps``); one over part of it
    splits the contact instead (:func:`split_rows`)."""
    return pit[2] if pit[3] >= 1.0 and pit[0] <= rho <= pit[1] else 0.0


@njit
def _static_pairs(loads, idx, cnt, flex, at, sd, count, ring):
    """``(p, p)`` ``b_a^T E^T K^-1 E b_c`` of the pairs' loads through the static blocks
    ``flex`` by the teeth's distance round the ring (``ring`` 1) or by the pair of teeth
    (0), over the loads' nonzeros."""
    p = loads.shape[0]
    res = np.zeros((p, p))
    for a in range(p):
        for c in range(p):
            fl = flex[(at[a] - at[c]) % count if ring else at[a] * count + at[c], sd[a], sd[c]]
            acc = 0.0
            for t in range(cnt[a]):
                i = idx[a, t]
                row = 0.0
                for u in range(cnt[c]):
                    j = idx[c, u]
                    row += fl[i, j] * loads[c, j]
                acc += loads[a, i] * row
            res[a, c] = acc
    return res


@njit
def masks_by_size(n):
    """All ``2^n`` masks, the fewest members first (ties in increasing order)."""
    out = np.empty(1 << n, np.int64)
    k = 0
    for m in range(n + 1):
        for mask in range(1 << n):
            c = 0
            x = mask
            while x:
                c += x & 1
                x >>= 1
            if c == m:
                out[k] = mask
                k += 1
    return out


@njit
def mask_orders():
    """The active sets to try, by size, for each count of pairs up to :data:`ORDERS`."""
    orders = np.full((ORDERS + 1, 1 << ORDERS), -1, np.int64)
    for k in range(ORDERS + 1):
        orders[k, :1 << k] = masks_by_size(k)
    return orders


@njit
def lcp_ordered(w, v, guess, orders):
    """``F >= 0`` with ``W F + v >= 0`` and ``F (W F + v) = 0`` (twin of ``lcp.lcp``): the
    active set ``guess`` (a mask) first, then the masks by size (``orders``, of
    :func:`mask_orders`). Returns ``(F, found)``."""
    n = v.size
    order = orders[n, :1 << n] if n <= ORDERS else masks_by_size(n)
    vmax = 0.0
    for i in range(n):
        vmax = max(vmax, abs(v[i]))
    tol = 1e-12 * max(vmax, 1e-300)
    f = np.zeros(n)
    idx = np.empty(n, np.int64)
    for attempt in range(-1, order.size):
        mask = guess if attempt == -1 else order[attempt]
        f[:] = 0.0
        m = 0
        for i in range(n):
            if mask >> i & 1:
                idx[m] = i
                m += 1
        ok = True
        if m:
            sol = _sub_solve(w, v, idx, m)
            for a in range(m):
                if sol[a] < 0.0:
                    ok = False
                f[idx[a]] = sol[a]
        if not ok:
            continue
        good = True
        for i in range(n):
            s = v[i]
            for c in range(n):
                s += w[i, c] * f[c]
            if s < -tol:
                good = False
                break
        if good:
            return f, True
    return f, False


@njit
def lcp_pivot(w, v, guess):
    """``(F, found)`` by block principal pivoting from the active set ``guess`` (booleans):
    twin of :func:`spurdyn.sector.lcp.lcp_pivot`, pivot for pivot."""
    n = v.size
    vmax = 0.0
    for i in range(n):
        vmax = max(vmax, abs(v[i]))
    tol = 1e-12 * max(vmax, 1e-300)
    act = guess.copy()
    best, tries = n + 1, BLOCK_TRIES
    f = np.zeros(n)
    bad = np.empty(n, np.int64)
    for _ in range(PIVOTS[0] * n + PIVOTS[1]):
        f = _active_solve(w, v, act)
        nb = 0
        for i in range(n):
            if act[i]:
                wrong = f[i] < 0.0
            else:
                s = v[i]
                for c in range(n):
                    s += w[i, c] * f[c]
                wrong = s < -tol
            if wrong:
                bad[nb] = i
                nb += 1
        if nb == 0:
            return f, True
        if nb < best or tries > 0:
            if nb < best:
                best, tries = nb, BLOCK_TRIES
            else:
                tries -= 1
            for a in range(nb):
                act[bad[a]] = not act[bad[a]]
        else:
            act[bad[nb - 1]] = not act[bad[nb - 1]]
    return np.zeros(n), False


@njit
def _active_solve(w, v, act):
    """``F`` with the active rows ``act`` solved (``W_AA F_A = -v_A``), zero elsewhere."""
    n = v.size
    idx = np.flatnonzero(act)
    m = idx.size
    f = np.zeros(n)
    if m:
        sol = _sub_solve(w, v, idx, m)
        for a in range(m):
            f[idx[a]] = sol[a]
    return f


@njit
def _sub_solve(w, v, idx, m):
    """``F_A`` of ``W_AA F_A = -v_A`` for the active rows ``idx[:m]``."""
    sub = np.empty((m, m))
    rhs = np.empty(m)
    for a in range(m):
        rhs[a] = -v[idx[a]]
        for c in range(m):
            sub[a, c] = w[idx[a], idx[c]]
    return np.linalg.solve(sub, rhs)


__all__ = ["ORDERS", "contact_rows", "lcp_pivot", "rows_and_loads", "damper_coefficient", "flank_load", "lcp_ordered", "mask_orders",
           "masks_by_size", "modal_free", "split_rows", "table_at"]

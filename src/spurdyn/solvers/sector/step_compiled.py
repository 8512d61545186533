"""The sector model's time loop on modal bodies of whole gears, compiled with Numba: the twin
of the NumPy loop in :mod:`spurdyn.solvers.sector.run` (docs/sector.md, 6.3), step for step
the same equations (the rows, the couplings, the mesh damper by Woodbury, the complementarity
problem by active sets with the step before's first, the generalized-alpha update).

Everything a step reads is an array or a scalar: per gear the inverse of ``S``, the modes'
damping and ``omega^2``, the modes at each flank in its own frame, the static flexibility
between two flanks by the teeth's distance round the ring, and the flank's geometry; the
contacts' teeth and flanks (0 the drive flanks, 1 the back flanks); the pair's rigid-gap
table; the scheme's constants. It runs ``steps`` steps from the
state it is given (changed in place) and writes the saved columns.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.jit import njit


@njit
def _table_at(t_rho, t_gap, t_slope, t_ra, t_rb, x):
    """The rigid gap's table at roll ``x`` (:meth:`GapTable.at`)."""
    n = t_rho.size
    i = np.searchsorted(t_rho, x, side="right") - 1
    i = min(max(i, 0), n - 2)
    if t_rho[i + 1] == t_rho[i]:
        i += 1
    x0 = t_rho[i]
    h = t_rho[i + 1] - x0
    u = (x - x0) / h
    g0, g1 = t_gap[i], t_gap[i + 1]
    d0, d1 = t_slope[i] * h, t_slope[i + 1] * h
    u2 = u * u
    u3 = u2 * u
    gap = (2 * u3 - 3 * u2 + 1) * g0 + (u3 - 2 * u2 + u) * d0 + (-2 * u3 + 3 * u2) * g1 + (u3 - u2) * d1
    slope = ((6 * u2 - 6 * u) * g0 + (3 * u2 - 4 * u + 1) * d0 + (-6 * u2 + 6 * u) * g1
             + (3 * u2 - 2 * u) * d1) / h
    r_a = t_ra[i] + u * (t_ra[i + 1] - t_ra[i])
    r_b = t_rb[i] + u * (t_rb[i + 1] - t_rb[i])
    return gap, slope, r_a, r_b


@njit
def _flank_load(geo, r, b, xq, wq, out):
    """The unit strip load at involute radius ``r``, half-width ``b``, on a flank in tooth 0's
    frame (:meth:`GearBlock.flank_loads`), into ``out`` (``2 (2 ny + 1)``)."""
    r0, r_tip, ny_f, rbase, hab = geo[0], geo[1], geo[2], geo[3], geo[4]
    ny = int(ny_f)
    slope = (r_tip - r0) / ny
    out[:] = 0.0
    for k in range(xq.size):
        rk = math.sqrt(max(r * r + 2.0 * rbase * b * xq[k], 0.0))
        t = min(max((rk - r0) / slope, 0.0), float(ny))
        row = min(int(math.floor(t)), ny - 1)
        eta = 2.0 * (t - row) - 1.0
        w0 = 0.5 * eta * (eta - 1.0) * wq[k]
        w1 = (1.0 - eta * eta) * wq[k]
        w2 = 0.5 * eta * (eta + 1.0) * wq[k]
        out[2 * (2 * row)] += w0
        out[2 * (2 * row + 1)] += w1
        out[2 * (2 * row + 2)] += w2
    # the mating flank pushes into the tooth, against the outward normal
    alpha = math.acos(min(max(rbase / r, -1.0), 1.0))
    chi = hab - math.tan(alpha)
    nx, nyy = math.cos(chi), -math.sin(chi)
    for j in range(2 * ny + 1):
        w = out[2 * j]
        out[2 * j] = -w * nx
        out[2 * j + 1] = -w * nyy


@njit
def _half_width(force, r_a, r_b, rb_a, rb_b, estar, width):
    rho_a = math.sqrt(max(r_a * r_a - rb_a * rb_a, 0.0))
    rho_b = math.sqrt(max(r_b * r_b - rb_b * rb_b, 0.0))
    if force == 0.0 or rho_a <= 0.0 or rho_b <= 0.0:
        return 0.0
    r_star = rho_a * rho_b / (rho_a + rho_b)
    return math.sqrt(4.0 * abs(force) * r_star / (math.pi * estar * width))


#: Counts of pairs near the path whose active sets the loop orders once (two to four occur).
ORDERS = 6


@njit
def _modal_free(tq0, tq1, q, v, inv0, inv1, damp0, damp1, om0, om1):
    """The bodies' accelerations without the contacts' forces: the hubs' torques ``tq0``,
    ``tq1`` less each mode's damping and stiffness at ``(q, v)``, through ``M^-1`` (or the
    implicit loop's ``S^-1``) as ``inv0``, ``inv1`` (the implicit loop and the RK4 reference)."""
    na = inv0.shape[0]
    n = na + inv1.shape[0]
    r = np.zeros(n)
    r[0] = tq0
    r[na] = tq1
    for j in range(om0.size):
        r[1 + j] -= damp0[j] * v[1 + j] + om0[j] * q[1 + j]
    for j in range(om1.size):
        r[na + 1 + j] -= damp1[j] * v[na + 1 + j] + om1[j] * q[na + 1 + j]
    out = np.empty(n)
    out[:na] = inv0 @ r[:na]
    out[na:] = inv1 @ r[na:]
    return out


@njit
def _masks_by_size(n):
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
def _lcp_ordered(w, v, guess, order):
    """``F >= 0`` with ``W F + v >= 0`` and ``F (W F + v) = 0`` (:func:`run._lcp`): the active
    set ``guess`` (a mask) first, then the masks of ``order``."""
    n = v.size
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
            sub = np.empty((m, m))
            rhs = np.empty(m)
            for a in range(m):
                rhs[a] = -v[idx[a]]
                for c in range(m):
                    sub[a, c] = w[idx[a], idx[c]]
            sol = np.linalg.solve(sub, rhs)
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
def run_steps(first_step, steps, q, v, acc, qdd, force,
              inv0, inv1, damp0, damp1, om0, om1, modes0, modes1, flex0, flex1,
              geo0, geo1, first0, first1, count0, count1,
              teeth, sides, offset, t_rho, t_gap, t_slope, t_ra, t_rb, consts, xq, wq, hub, c_table,
              th_out, om_out, f_out, gap_out):
    """``steps`` steps from ``first_step`` (the state changed in place, the saved columns
    written at ``first_step + 1 ...``). ``consts``: ``roll_0, roll_1, reach, pitch, r_bA,
    r_bB, E*, L, c_H, alpha_m, alpha_f, beta, gamma, h, beta', gamma', Sigma, j_n, theta_lo,
    theta_hi`` (the back flanks' roll sum and the backlash, ``system.back_roll_sum``; the
    driver's turns the contacts cover); ``hub`` the hubs' torques at the end of each step;
    ``c_table`` the mesh damper's coefficient over a pitch (``damper.mesh_damper_table``, read
    as ``damper.damper_at``). Contact ``i`` is the driver's tooth ``teeth[i]`` on its flank
    ``sides[i]``.

    Returns the last step done and 0, or the step whose solution was not finite and 1, or the
    step at whose end the driver had left ``theta_lo .. theta_hi`` and 2."""
    roll_0, roll_1, reach, pitch = consts[0], consts[1], consts[2], consts[3]
    ra, rb, estar, width, c_h = consts[4], consts[5], consts[6], consts[7], consts[8]
    am, af, beta, gamma, h, bp, gp = consts[9], consts[10], consts[11], consts[12], consts[13], consts[14], consts[15]
    sigma, jn, theta_lo, theta_hi = consts[16], consts[17], consts[18], consts[19]
    n_damp = c_table.size - 1
    na = inv0.shape[0]
    nb = inv1.shape[0]
    n = na + nb
    m0 = om0.size
    m1 = om1.size
    nf = modes0.shape[2]
    nt = teeth.size
    z0 = inv0[:, 0].copy()
    z1 = inv1[:, 0].copy()
    inv0_e = inv0[:, 1:].copy()
    inv1_e = inv1[:, 1:].copy()
    # the active sets to try, by size, for each count of pairs up to ORDERS (made once)
    orders = np.full((ORDERS + 1, 1 << ORDERS), -1, np.int64)
    for k in range(ORDERS + 1):
        orders[k, :1 << k] = _masks_by_size(k)
    loads0 = np.empty((nt, nf))
    loads1 = np.empty((nt, nf))
    for step in range(first_step + 1, first_step + steps + 1):
        a_part = (af * qdd - am * acc) / (1.0 - am)
        q_hat = q + h * v + h * h * (0.5 - beta) * acc + h * h * beta * a_part
        v_hat = v + h * (1.0 - gamma) * acc + h * gamma * a_part
        x0 = _modal_free(hub[step, 0], hub[step, 1], q_hat, v_hat, inv0, inv1, damp0, damp1, om0, om1)
        theta = q_hat[0]
        # the contacts near their paths (a back flank's roll runs backwards: system.back_roll_sum)
        on = np.empty(nt, np.int64)
        p = 0
        for i in range(nt):
            roll = roll_0 + theta + teeth[i] * pitch
            if sides[i]:
                roll = sigma - roll
            if roll >= roll_0 - reach and roll <= roll_1 + reach:
                on[p] = i
                p += 1
        last = force.copy()
        force[:] = 0.0
        if p == 0:
            qdd_new = x0
        else:
            const = np.empty(p)
            coef0 = np.empty(p)
            coef1 = np.empty(p)
            at0 = np.empty(p, np.int64)
            at1 = np.empty(p, np.int64)
            sd = np.empty(p, np.int64)
            for a in range(p):
                i = on[a]
                sd[a] = sides[i]
                # d roll / d theta_A: +1 on a drive flank, -1 on a back flank
                sgn = -1.0 if sd[a] else 1.0
                rho = roll_0 + theta + teeth[i] * pitch
                if sd[a]:
                    rho = sigma - rho
                g0, slope, r_a, r_b = _table_at(t_rho, t_gap, t_slope, t_ra, t_rb, rho)
                hw = _half_width(last[i], r_a, r_b, geo0[3], geo1[3], estar, width)
                const[a] = g0 - sgn * slope * theta + (jn if sd[a] else 0.0)
                coef0[a] = sgn * (slope - ra)
                coef1[a] = sgn * rb
                k = teeth[i] + offset
                at0[a] = (k - first0) % count0
                at1[a] = (-k + sd[a] - first1) % count1
                _flank_load(geo0, r_a, hw, xq, wq, loads0[a])
                _flank_load(geo1, r_b, hw, xq, wq, loads1[a])
            rows0 = np.empty((p, m0))
            rows1 = np.empty((p, m1))
            for a in range(p):
                rows0[a] = loads0[a] @ modes0[at0[a], sd[a]]
                rows1[a] = loads1[a] @ modes1[at1[a], sd[a]]
            # couplings (docs/sector.md 6.3): per gear S^-1 G^T = z c^T + S^-1 E^T
            full0 = np.outer(z0, coef0) + inv0_e @ rows0.T
            full1 = np.outer(z1, coef1) + inv1_e @ rows1.T
            w0 = (np.outer(coef0, full0[0]) + rows0 @ full0[1:]
                  + np.outer(coef1, full1[0]) + rows1 @ full1[1:])
            w_gd = (np.outer(coef0 * z0[0] + rows0 @ z0[1:], coef0)
                    + np.outer(coef1 * z1[0] + rows1 @ z1[1:], coef1))
            w_dd = z0[0] * np.outer(coef0, coef0) + z1[0] * np.outer(coef1, coef1)
            res = np.zeros((p, p))
            for a in range(p):
                for c in range(p):
                    d0 = (at0[a] - at0[c]) % count0
                    d1 = (at1[a] - at1[c]) % count1
                    res[a, c] = (loads0[a] @ (flex0[d0, sd[a], sd[c]] @ loads0[c])
                                 + loads1[a] @ (flex1[d1, sd[a], sd[c]] @ loads1[c]))
            res -= (rows0 / om0) @ rows0.T + (rows1 / om1) @ rows1.T
            # the mesh damper, shared by the forces of the step before
            shares = np.empty(p)
            total = 0.0
            guess = 0
            for a in range(p):
                shares[a] = last[on[a]]
                total += shares[a]
                if shares[a] > 0.0:
                    guess |= 1 << a
            # the damper's coefficient at this phase (damper.damper_at)
            x_d = (theta % pitch) / pitch * n_damp
            i_d = min(int(x_d), n_damp - 1)
            f_d = x_d - i_d
            c_mesh = c_table[i_d] * (1.0 - f_d) + c_table[i_d + 1] * f_d
            c_pairs = np.zeros(p)
            damped = False
            if c_mesh > 0.0 and total > 0.0:
                c_pairs = c_mesh * shares / total
                for a in range(p):
                    if c_pairs[a] != 0.0:
                        damped = True
            if damped:
                rate = c_pairs * (coef0 * v_hat[0] + coef1 * v_hat[na])
                x0[:na] -= (coef0 @ rate) * z0
                x0[na:] -= (coef1 @ rate) * z1
            g_x0 = coef0 * x0[0] + rows0 @ x0[1:na] + coef1 * x0[na] + rows1 @ x0[na + 1:]
            d_x0 = coef0 * x0[0] + coef1 * x0[na]
            if damped:
                gc = gp * c_pairs
                k_w = np.empty((p, p))
                inv_m = np.linalg.inv(np.eye(p) + w_dd * gc.reshape(1, p))
                for a in range(p):
                    k_w[a] = gc[a] * inv_m[a]
            else:
                k_w = np.zeros((p, p))
            w = bp * (w0 - w_gd @ k_w @ w_gd.T) + res + c_h * np.eye(p)
            vv = (const + coef0 * q_hat[0] + rows0 @ q_hat[1:na] + coef1 * q_hat[na] + rows1 @ q_hat[na + 1:]
                  + bp * (g_x0 - w_gd @ (k_w @ d_x0)))
            order = orders[p, :1 << p] if p <= ORDERS else _masks_by_size(p)
            lam, found = _lcp_ordered(0.5 * (w + w.T), vv, guess, order)
            if not found:
                return step, 1
            qdd_new = x0.copy()
            qdd_new[:na] += full0 @ lam
            qdd_new[na:] += full1 @ lam
            kd = k_w @ (d_x0 + w_gd.T @ lam)
            qdd_new[:na] -= (coef0 @ kd) * z0
            qdd_new[na:] -= (coef1 @ kd) * z1
            for a in range(p):
                force[on[a]] = lam[a]
        for j in range(n):
            if not math.isfinite(qdd_new[j]):
                return step, 1
        acc[:] = a_part + (1.0 - af) / (1.0 - am) * qdd_new
        q[:] = q_hat + bp * qdd_new
        v[:] = v_hat + gp * qdd_new
        qdd[:] = qdd_new
        if q[0] < theta_lo or q[0] > theta_hi:
            return step, 2
        th_out[step, 0] = q[0]
        th_out[step, 1] = q[na]
        om_out[step, 0] = v[0]
        om_out[step, 1] = v[na]
        f_out[step] = force
        if p:
            fo = np.empty(p)
            for a in range(p):
                fo[a] = force[on[a]]
            gaps = (const + coef0 * q[0] + rows0 @ q[1:na] + coef1 * q[na] + rows1 @ q[na + 1:]
                    + c_h * fo + res @ fo)
            gap_out[step] = gaps.min()
    return first_step + steps, 0

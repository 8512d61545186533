"""Print the ISO 6336 figures of the two worked examples of ``docs/iso6336.md``.

    .venv/bin/python -m spurdyn.iso6336
"""

from __future__ import annotations

import math

from spurdyn.iso6336.rating import IsoGear, IsoPair, IsoRating, dynamic_factor_at, iso_pair, rate

RPM = math.pi / 30.0  # rad/s per min^-1


def example_pair() -> IsoPair:
    """Worked example (ii): 23/47 teeth, m = 2 mm, 25 deg, b = 20 mm, ISO 53 profile A-like rack."""
    m = 2e-3

    def gear(z: int) -> IsoGear:
        return IsoGear(teeth=z, tip_radius=0.5 * m * z + m, rack_dedendum=1.25 * m,
                       rack_tip_radius=0.38 * m)

    return IsoPair(gear1=gear(23), gear2=gear(47), module=m, pressure_angle=math.radians(25.0),
                   face_width=20e-3)


def report(name: str, r: IsoRating, speeds_rpm: tuple[float, ...]) -> str:
    """The figures as text (MPa, rpm, N/(mm um) at the edges)."""
    lines = [name,
             f"  F_t = {r.tangential_force:.6g} N, K_A F_t/b = {r.line_load * 1e-3:.6g} N/mm",
             f"  eps_alpha = {r.eps_alpha:.6f}  Z_H = {r.z_h:.6f}  Z_E = {r.z_e * 1e-3:.6f} sqrt(MPa)"
             f"  Z_eps = {r.z_eps:.6f}  Z_B = {r.z_b:.6f}  Z_D = {r.z_d:.6f}",
             f"  sigma_H0 = {r.sigma_h0 * 1e-6:.6g} MPa"]
    for i, s in enumerate(r.sections):
        lines.append(f"  gear {i + 1}: theta = {math.degrees(s.theta):.6f} deg  s_Fn = {s.s_fn * 1e3:.6f} mm"
                     f"  rho_F = {s.rho_f * 1e3:.6f} mm  h_Fe = {s.h_fe * 1e3:.6f} mm"
                     f"  alpha_Fen = {math.degrees(s.alpha_fen):.6f} deg  d_en = {s.d_en * 1e3:.6f} mm")
        lines.append(f"          Y_F = {r.y_f[i]:.6f}  Y_S = {r.y_s[i]:.6f}"
                     f"  sigma_F0 = {r.sigma_f0[i] * 1e-6:.6g} MPa")
    lines.append(f"  c' = {r.single_pair * 1e-9:.6f} N/(mm um)  c_gamma_alpha = {r.mesh * 1e-9:.6f}"
                 f" N/(mm um)  m_red = {r.reduced_mass:.6g} kg  n_E1 = {r.resonance_speed / RPM:.6g} rpm")
    for n in speeds_rpm:
        kv = dynamic_factor_at(r, n * RPM)
        lines.append(f"  at {n:g} rpm: N = {n * RPM / r.resonance_speed:.6f}, K_v = {kv:.6f}"
                     " (perfect gears, no tip relief)")
    return "\n".join(lines)


def main() -> None:
    from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair

    print(report("(i) paper's pair, 22.25 N m", rate(iso_pair(paper_pair()), PAPER_TORQUE),
                 (4000.0, 20000.0)))
    print(report("(ii) 23/47, m 2 mm, 25 deg, 100 N m", rate(example_pair(), 100.0), (3000.0,)))


if __name__ == "__main__":
    main()

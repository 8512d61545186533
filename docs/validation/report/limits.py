"""Section 6 of the report: what the model leaves out, and when it matters."""

from __future__ import annotations

import math

import numpy as np

from .context import Ctx
from .convergence import clamped_tooth_modes
from .helpers import upct
from .settings import RPM
from .spurdyn_api import build_tooth


def section_limits(ctx: Ctx) -> str:
    """Section 6: the model's omissions, with the figures that size them."""
    pair = ctx.pair
    g = pair.gear_a
    mat = g.material
    face = g.face_width
    # Hertzian half-width at the pitch point under the static load
    rho = g.pitch_radius * math.sin(pair.working_pressure_angle)
    r_eq = rho * rho / (2 * rho)
    e_star = mat.young / (2 * (1 - mat.poisson ** 2))
    b_h = math.sqrt(4 * (ctx.static / face) * r_eq / (math.pi * e_star))
    edges = {}
    for nx, ny in ((4, 14), (8, 28)):
        tooth = build_tooth(g, nx, ny)
        side = tooth.mesh.nodes[tooth.mesh.right_side[::2]]
        edges[(nx, ny)] = float(np.min(np.linalg.norm(np.diff(side, axis=0), axis=1)))
    # sliding speed at the ends of contact
    slide = {rpm: g.base_radius * rpm * RPM * abs(pair.end_roll_a - pair.start_roll_a)
             for rpm in (4000, 20000)}
    double_share = 2 * pair.theta_2 / pair.theta_s
    clamped = clamped_tooth_modes(pair, 4, 14, 1)[0]
    tooth_mass = build_tooth(g, 4, 14).tooth_mass
    text = f"""
## 6. Limits: what the model leaves out, and when it matters

* **The other teeth.** One tooth per gear; the second pair, in contact during
  {upct(double_share, 0)} of the engagement (contact ratio {pair.contact_ratio:.3f}), is
  replaced by the prescribed torque ramps of Fig. 7. The load sharing between the pairs
  is therefore an input, not a result: the model cannot show the load jump at the
  highest and lowest points of single contact of real gears, the mesh-stiffness
  excitation from one to two pairs, nor the effect of a relief or of tooth errors on
  load sharing (section 5 shows what goes wrong). It matters for every result in the
  double-contact zones, and most where the teeth separate there (rattling, relief).
* **One engagement, from rest of the elastic system.** Each run starts with undeformed
  teeth just touching and ends after θs; there is no steady state, no previous
  engagement's vibration. Dynamic factors are those of a transient, and the undamped
  oscillation set off by the torque ramps and the stiffness variation is in every figure.
* **Shafts, bearings and the rest of the gear body.** The disks are rigid, pinned on
  fixed centres, with the paper's J = {g.disk_inertia:.4g} kg m²; no shaft torsion or
  bending, no bearing or housing compliance, no motor or load inertia, and no rim or web
  compliance under the root circle (a main reason the pair is
  {ctx.figures['iso_ratio']:.1f} times as stiff as ISO's c′, section 3.3). Shaft and bearing modes couple with the mesh at the speeds where their
  frequencies meet the mesh frequency; none of that is in the model.
* **No damping.** Neither material nor lubricant damping; oscillations never decay
  (section 3.1), and dynamic factors near resonance are upper bounds.
* **Friction.** Frictionless contact. The flanks slide at up to
  {slide[4000]:.1f} m/s at 4,000 rpm and {slide[20000]:.0f} m/s at 20,000 rpm at the ends
  of contact, changing sign at the pitch point; a friction coefficient of a few per cent
  (lubricated steel) would add a tangential force of that fraction of the normal force,
  reversing at the pitch point, whose moment arm about each centre is the contact point's
  roll length ({pair.start_roll_length_a * 1e3:.1f}–{pair.end_roll_length_a * 1e3:.1f} mm, against
  r_b = {g.base_radius * 1e3:.1f} mm for the normal force): with μ = 0.05, a change of the
  disks' torques of up to {upct(0.05 * pair.end_roll_length_a / g.base_radius, 1)}, and an
  excitation at the pitch point that matter for noise and efficiency, little for the
  peak normal force.
* **Two dimensions.** Plane stress with the face width as thickness; no lead or
  crowning, no misalignment, no load distribution across the face. For a
  {face * 1e3:.2f} mm face with perfect alignment this is a fair model; for wide or
  misaligned gears the load concentrates at one end of the face.
* **Hertzian flattening at the Q8 mesh's resolution.** The contact force is a point load
  on the element edge. Under the static load the Hertzian contact half-width at the
  pitch point is b_H = {b_h * 1e3:.3f} mm, against a shortest flank element edge of
  {edges[(4, 14)] * 1e3:.3f} mm on the default 4 × 14 mesh ({edges[(8, 28)] * 1e3:.3f} mm on
  8 × 28): the mesh smears the load over one element instead of the contact width, the
  local contact compliance is resolved only to the mesh's scale (it keeps growing with
  refinement, section 2.1), and the model gives no contact pressure or subsurface
  stress. Tooth-root stresses, bending and the pair's overall stiffness are resolved.
* **Tooth inertia is there, but coarse.** The teeth ({tooth_mass * 1e3:.2f} g each) have
  their own modes from {clamped / 1e3:.0f} kHz up; they ring at every element crossing
  (section 2.1). Their effect on the disks' dynamics is small at these speeds.
* **Numerical robustness.** Runs on meshes finer than the default can stop with a
  non-converged displacement stage in impacts or at high load, when the flank splines
  have too few data points per element or the mesh resolves the dent of the point load
  (section 2.1). A stopped run keeps what it computed and says so (`status =
  "incomplete"`).{" So does the paper's Fig. 11 with gear B driving at Δt = 3 × 10⁻⁸ s." if ctx.figures.get("fig11_b_failed") else ""}
"""
    return text



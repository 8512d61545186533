from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.system import system_for
from spurdyn.solvers.paper.statics import static_stiffness
pair = paper_pair(); force = PAPER_TORQUE / pair.gear_a.base_radius
for nx, ny, gr in ((4, 14, 1.0), (12, 40, 1.0), (24, 80, 1.0), (12, 40, 6.0), (24, 80, 6.0)):
    s = system_for(pair, nx, ny, 61, gr)
    print(nx, ny, gr, '%.5e' % static_stiffness(s, pair.pitch_roll_a, force, "hertz").stiffness)

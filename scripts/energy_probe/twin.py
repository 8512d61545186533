import numpy as np
from spurdyn.geometry.presets import paper_pair, PAPER_TORQUE
from spurdyn.settings import RunSettings
from spurdyn.model.system import build_system
from spurdyn.solvers.paper.stepper_compiled import CompiledStepper
from spurdyn.solvers.paper.step_numpy import PaperMethod, initial_state
RPM = 2*np.pi/60
PAIR = paper_pair()
case = RunSettings(speed_a=20000 * RPM, speed_b=20000 * RPM, torque=PAPER_TORQUE, contact="hertz")
system = build_system(PAIR, case)
fast, ref = CompiledStepper(system, case), PaperMethod(system, case)
st = initial_state(system, case)
for i in range(300):
    fast.step(); st, rep = ref.step(st, i + 1); S = fast.S
    du = np.abs(S.u - st.u).max()
    if i % 10 == 0 or du > 1e-14:
        print(i+1, 'du %.2e dp %.2e da %.2e db %.2e dn %.2e hw %.3e dhw %.1e its %s %s' % (du, abs(S.x[-1]-st.x[-1]), abs(S.cpar[0]-st.contact.alpha), abs(S.cpar[1]-st.contact.beta), np.abs(S.normal-st.contact.normal).max(), st.contact.half_width, abs(S.cpar[5]-st.contact.half_width), S.its, rep.iterations))
    if du > 1e-13: break

# # A tuned ring of shrouded blades: linear limits, the travelling wave by one sector, the ring in time
#
# The paper holds the blade's neighbours fixed. On a disk they move: with
# ``ring.blades = N`` the workbench puts N blades on a rigid disk, each
# shroud touching its neighbours' through the one contact law (penalty
# normal, Jenkins friction), under the engine-order travelling wave
# F_0 sin(k_e Omega t + 2 pi k_e j / N) (docs/ring.md, geometry.md).
#
# This script uses ``shroud.api`` alone and holds each answer to a number
# from elsewhere:
#
# 1. With free interfaces every blade vibrates alone, so the ring's
#    frequencies at every nodal diameter are the single blade's: the
#    one-sector (Bloch) reduction against the blade's own modal analysis.
# 2. With the shrouds in contact, the tuned travelling wave by one sector
#    (harmonic balance, each neighbour's harmonics phase-shifted by
#    exp(i h phi)) against the whole ring of 6 blades integrated in time
#    from rest, blade by blade.

import numpy as np

from shroud import api

ring = api.parameters({"ring.blades": 6, "speed.rpm": 6000.0})

# ## 1. The free ring is the blade, at every nodal diameter

free = api.linear_limits(ring, "reduced", interface="free", n_modes=4, coriolis=False).to_json()
blade = api.modal(api.parameters({"speed.rpm": 6000.0}), "reduced", n_modes=4, coriolis=False)
alone = np.array([m.f_hz for m in blade.modes])
print("free interfaces, Hz, per nodal diameter:")
for nd in free["nodal_diameters"]:
    f = np.array([m["f_hz"] for m in nd["modes"]])
    print(f"  nd {nd['nd']}: " + "  ".join(f"{x:8.2f}" for x in f))
    assert np.allclose(f, alone, rtol=1e-8), (nd["nd"], f, alone)
print("  the blade alone: " + "  ".join(f"{x:8.2f}" for x in alone))

stuck = api.linear_limits(ring, "reduced", interface="stuck", n_modes=2, coriolis=False).to_json()
print("stuck interfaces (contacts as springs kn, kt), first two modes, Hz:")
for nd in stuck["nodal_diameters"]:
    print(f"  nd {nd['nd']}: " + "  ".join(f"{m['f_hz']:8.2f}" for m in nd["modes"]))

# ## 2. The travelling wave by one sector against the ring in time
#
# Engine order 2 on 6 blades: inter-blade phase 120 deg. The impacts need
# 20 harmonics (10 leave the amplitude 3.5 % low here, docs/ring.md).

wave = api.continuation(ring, "reduced", 5990.0, 6000.0, harmonics=20)
hb_amplitude = wave.to_json()["amplitude_v_L"][-1]
in_time = api.transient(ring.updated({"time.periods": 200}), "reduced").to_json()
blades = np.array([b["amplitude"]["v_L"] for b in in_time["blades"]])
print(f"6000 r/min: travelling wave by one sector {hb_amplitude * 1e6:.4f} um; "
      f"the ring in time, blade by blade: " + ", ".join(f"{a * 1e6:.4f}" for a in blades) + " um")
assert np.all(np.abs(blades / hb_amplitude - 1) < 0.005)

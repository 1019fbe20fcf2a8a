# # The workbench as a library: Table 1, the Fig. 8 point and a harmonic-balance branch
#
# Everything the command line does is one call of ``shroud.api``, returning
# a results object that serializes (``to_json``) and draws itself
# (``plot``). This script uses nothing else, and holds each answer to a
# number from outside the call that made it:
#
# 1. Table 1 of the paper (Guo et al. 2020): the rotating beam's first four
#    natural frequencies at 8500 r/min, against the paper's own N = 6 beam;
# 2. the Fig. 8 operating point (10000 r/min, shroud touching, mu = 0.3):
#    the time response by Newmark against the periodic steady state by
#    harmonic balance, two methods on one model;
# 3. a branch of steady states over speed by harmonic balance with
#    continuation at a 0.1 mm gap, against time-domain runs that settle,
#    at speeds where the branch has one state.

import numpy as np

from shroud import api

# ## 1. Table 1: natural frequencies at 8500 r/min
#
# The paper's beam with N = 6 shape functions per field (its Table 1 row,
# Hz). The paper does not publish its basis functions, so the two N = 6
# discretizations differ slightly; its converged (ANSYS) column is 0.5-1 %
# below the row.

PAPER_N6 = {"flap1": 284.2, "chord1": 1119.9, "flap2": 1502.0, "flap3": 3968.3}

table1 = api.modal(api.parameters({"reduced.N": 6}), "reduced", rpm=8500.0, n_modes=6, coriolis=False)
ours = table1.by_label()
print("Table 1 at 8500 r/min (Hz):")
for label, paper in PAPER_N6.items():
    print(f"  {label:7s} ours {ours[label]:8.1f}   paper {paper:8.1f}   {ours[label] / paper - 1:+.2%}")
    assert abs(ours[label] / paper - 1) < 0.01, label

# ## 2. The Fig. 8 point: Newmark against harmonic balance
#
# 100 excitation periods from rest (the paper's run); the amplitude is
# (max - min) / 2 of the flexural tip displacement over the last 10.

fig8 = api.parameters({"speed.rpm": 10000.0})
run = api.transient(fig8, "reduced")
steady = api.harmonic_balance(fig8, "reduced", rpm=10000.0)
print(f"Fig. 8 point: v_L amplitude {run.amplitude['v_L'] * 1e6:.4f} um by Newmark "
      f"({run.elapsed_s:.2f} s), {steady.amplitude_v_L * 1e6:.4f} um by harmonic balance "
      f"({steady.elapsed_s:.2f} s, stable: {steady.stable})")
assert abs(run.amplitude["v_L"] / steady.amplitude_v_L - 1) < 0.01

# ## 3. A branch over speed at a 0.1 mm gap
#
# The continuation follows the steady state through the impacts' folds;
# each point carries its Floquet stability. Where the branch folds, two
# stable states coexist and a run from rest lands on one of them, so the
# time domain is held against the branch where it passes a speed once.

gapped = api.parameters({"contact.gap": 1e-4})
branch = api.continuation(gapped, "reduced", 5000.0, 20000.0)
peak = branch.resonance
print(f"HB branch: {len(branch.rpm)} points in {branch.elapsed_s:.2f} s; resonance "
      f"{peak['amplitude'] * 1e6:.2f} um at {peak['rpm']:.0f} r/min")
rpm = np.asarray(branch.rpm)
for speed in (8000.0, 16000.0):
    passes = int(np.sum(np.diff(np.sign(rpm - speed)) != 0))
    assert passes == 1, (speed, passes)                       # one state on the branch at this speed
    on_branch = api.harmonic_balance(gapped, "reduced", rpm=speed)
    settled = api.sweep(gapped, "reduced", [speed])
    print(f"  {speed:.0f} r/min: HB {on_branch.amplitude_v_L * 1e6:.3f} um (stable: {on_branch.stable}), "
          f"time domain {settled.amplitude_v_L[0] * 1e6:.3f} um (settled: {bool(settled.settled[0])})")
    assert settled.settled[0] and abs(settled.amplitude_v_L[0] / on_branch.amplitude_v_L - 1) < 0.01

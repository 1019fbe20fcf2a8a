# # The paper's Fig. 8 case on the beams: reduced against full
#
# This example runs the impact-friction transient of the paper's Fig. 8
# (10000 r/min, no preload N0 = 0, shroud angle alpha = 15 deg, kn = kt =
# 1e7 N/m, mu = 0.3, 100 excitation periods of 256 steps from rest) on two
# beam models:
#
# * the full beam: N = 6 shape functions per field, 30 DOF;
# * the reduced beam: the full beam projected on its nr = 6 free-interface
#   modes (paper Sect. 2.1.2), 6 DOF.
#
# It compares their contact forces (N1, N2, friction Ff1, Ff2) and tip
# displacements (v_L, w_L) over the last 10 periods by the normalized RMS
# error the fig8 study reports (shroud/analysis/agreement.py), and checks that
# the reduction keeps the full beam's response to within 1 %, the
# workbench's target for a reduced model (the README measures 0.46 %; the
# paper's Fig. 8 shows the two curves on top of each other).

from shroud.analysis.agreement import SIGNALS, agreement, signals_of
from shroud.analysis.api import transient
from shroud.params import Parameters

# ## The parameters
#
# The defaults are the paper's Table 2 and the Fig. 8 case; the scene file
# scenes/fig8.toml says the same.

params = Parameters.from_mapping({"speed": {"rpm": 10000.0}, "contact": {"N0": 0.0, "kn": 1e7, "kt": 1e7,
                                                                          "mu": 0.3, "alpha_deg": 15.0},
                                  "time": {"periods": 100, "steps_per_period": 256}})
period = 60.0 / (params.load.ke * params.speed.rpm)          # excitation period, s

# ## The two runs

runs = {model: transient(params, model) for model in ("full", "reduced")}
for model, run in runs.items():
    print(f"{model:8s} {run.dofs:3d} DOF: v_L amplitude {1e6 * run.amplitude['v_L']:.2f} um, "
          f"peak N1 {run.peak['N1']:.1f} N, slip share side 1 {run.state_fraction['side1']['slip']:.2f}")

# ## The agreement
#
# Over the full model's last 10 periods: RMS of the difference over the
# full model's peak-to-peak range, per signal.

full, reduced = runs["full"].trajectory, runs["reduced"].trajectory
result = agreement(reduced.t, signals_of(reduced), full.t, signals_of(full), period, periods=10)
for name in SIGNALS:
    print(f"NRMSE {name:4s} {100 * result.nrmse[name]:.3f} %")

# ## The check

assert result.worst_nrmse < 0.01, result.nrmse
print(f"worst NRMSE {100 * result.worst_nrmse:.2f} % < 1 %: the reduced beam reproduces the full one")

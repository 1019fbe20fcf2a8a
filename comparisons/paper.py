"""Published values of Guo et al. (2020), kept in one place for every study.

Frequencies in Hz, times in s. The paper's mode order at 8500 r/min is
flap1, chord1, flap2, flap3 (its beam models restrain torsion).
"""

# Table 1: first four frequencies at 8500 r/min.
TABLE1_RPM = 8500.0
TABLE1_LABELS = ("flap1", "chord1", "flap2", "flap3")
TABLE1_REDUCED = {4: (286.0, 1121.2, 1506.7, 3975.1), 5: (285.3, 1120.9, 1502.9, 3972.6),
                  6: (284.2, 1119.9, 1502.0, 3968.3), 7: (283.6, 1119.9, 1500.8, 3969.7)}
TABLE1_FE = (282.4, 1117.0, 1497.5, 3958.1)     # ANSYS Beam188 + Mass21, torsion restrained

# Table 3: run time of 100 excitation periods at 10000 r/min (Fig. 8 case), i7-6700.
TABLE3_SECONDS = {"reduced": 5.37, "full": 7.66, "fe-reduced": 2328.84, "fe": 3259.67}

# Sect. 2.2.2, Fig. 10: the reduced shell FE model (Shell181, 24 modes, 11 contact elements per face),
# 100 excitation periods of the Fig. 8 case at 10000 r/min; no figure for the full shell.
FIG10_SECONDS = {"shell-reduced": 2605.71}
PAPER_SECONDS = {**TABLE3_SECONDS, **FIG10_SECONDS}     # a model's run time in the paper, where given

# Sect. 2.2.1, Fig. 4: the reduced model's run time as a share of the full model's.
FIG4_TIME_SHARE = 0.7

# Sect. 3.1, Fig. 11: primary resonance of v_L at a 0.6 mm gap (2 f_e near flap1, 284.2 Hz).
FIG11_GAP_M = 0.6e-3
FIG11_RESONANCE_RPM = 8500.0

# Sect. 3.2, Fig. 12(f): band of the P10 fluctuation at mu = 0.5 under preloads, r/min.
P10_MU = 0.5
P10_BAND_RPM = (22500.0, 26000.0)

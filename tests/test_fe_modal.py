"""The solid FE modal analysis against independent truths.

* a straight, untwisted, unshrouded cantilever at rest against the exact
  Timoshenko-beam frequencies (transfer-matrix solution of the two coupled
  ODEs, computed here; nu = 0 so that beam theory has no Poisson error);
* the same beam rotating, against the published rotating-cantilever table
  (Hodges & Rutkowski 1981; Wright et al. 1982: hub ratio 0, first flapwise
  lambda = omega sqrt(rho A L^4 / EI) = 3.5160, 4.1373, 6.4495 at speed
  parameter gamma = Omega sqrt(rho A L^4 / EI) = 0, 2, 5), out of the plane
  of rotation (no spin softening) and in it (lambda_in^2 = lambda^2 - gamma^2);
* the gyroscopic frequencies (Rayleigh-Ritz on [Phi, K^-1 G Phi]) against
  a second method: scipy's Arnoldi on the full first-order (state-space)
  form built from the exported CSR operators;
* mesh convergence towards the exact value;
* the default blade at 8500 r/min against the paper's FE first frequency;
* serial and `mpirun -n 2` runs of `shroud modal --model fe` agreeing.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse.linalg as spla
from scipy.optimize import brentq

pytestmark = pytest.mark.fe

from shroud.params import Parameters  # noqa: E402

E, RHO = 200e9, 7800.0
L, B, H = 0.2, 0.02, 0.01      # slender (L/h = 20) straight beam, thickness h along e_v


def beam(stagger_deg: float, size: float = 0.005, cell: str = "tet", **more) -> Parameters:
    """Straight, untwisted, unshrouded, hub ratio 0, nu = 0 cantilever (tetrahedra unless asked)."""
    return Parameters().updated({"fe.cell": cell,
        "blade.length": L, "blade.width": B, "blade.thickness": H, "blade.disk_radius": 0.0,
        "blade.stagger_deg": stagger_deg, "blade.twist_deg": 0.0, "shroud.thickness": 0.0,
        "material.E": E, "material.rho": RHO, "material.nu": 0.0, "fe.mesh_size": size, **more})


def timoshenko_cantilever(depth: float, width: float, nu: float, count: int) -> np.ndarray:
    """Exact clamped-free Timoshenko frequencies (Hz) for bending across ``depth``.

    State y = [w, w', psi, psi'] of  kGA (w'' - psi') + rho A om^2 w = 0,
    EI psi'' + kGA (w' - psi) + rho I om^2 psi = 0; y(L) = expm(A L) y(0) with
    w(0) = psi(0) = 0, and at L: EI psi' = 0, kGA (w' - psi) = 0. Cowper's
    shear coefficient of a rectangle, 10 (1 + nu) / (12 + 11 nu).
    """
    G = E / (2 * (1 + nu))
    A, I = depth * width, width * depth**3 / 12
    kGA = 10 * (1 + nu) / (12 + 11 * nu) * G * A

    def det(om):
        Amat = np.array([[0, 1, 0, 0], [-RHO * A * om**2 / kGA, 0, 0, 1], [0, 0, 0, 1],
                         [0, -kGA / (E * I), (kGA - RHO * I * om**2) / (E * I), 0]])
        T = sla.expm(Amat * L)[:, [1, 3]]
        return np.linalg.det(np.array([T[3], T[1] - T[2]]))

    grid = np.linspace(10.0, 2e5, 20000)
    values = np.array([det(om) for om in grid])
    roots = [brentq(det, grid[i], grid[i + 1]) for i in np.flatnonzero(np.diff(np.sign(values)))]
    return np.array(roots[:count]) / (2 * np.pi)


def speed_time_scale() -> float:
    """T with gamma = Omega T: sqrt(rho A L^4 / EI) for bending across h, s."""
    return L**2 / H * math.sqrt(12 * RHO / E)


@pytest.mark.parametrize("cell", ["tet", "hex"])
def test_straight_cantilever_matches_timoshenko(cell):
    from reference_fe.modal import solve_modes
    modes = solve_modes(beam(90.0, cell=cell), rpm=0.0, n_modes=3, coriolis=False)
    assert modes.labels == ("flap1", "chord1", "flap2")
    flap = timoshenko_cantilever(H, B, 0.0, 2)
    chord = timoshenko_cantilever(B, H, 0.0, 1)
    exact = np.array([flap[0], chord[0], flap[1]])
    assert np.allclose(modes.f_undamped, exact, rtol=5e-4), (modes.f_undamped, exact)


@pytest.mark.parametrize("cell", ["tet", "hex"])
@pytest.mark.parametrize("gamma, published", [(2.0, 4.1373), (5.0, 6.4495)])
def test_rotating_cantilever_matches_published_table(gamma, published, cell):
    """Flap out of the plane of rotation (stagger 90 deg: e_v = Z) and in it (stagger 0: e_v = Y)."""
    from reference_fe.modal import solve_modes
    T = speed_time_scale()
    rpm = gamma / T * 60 / (2 * math.pi)
    at_rest = 2 * math.pi * solve_modes(beam(90.0, cell=cell), 0.0, 1, False).f_undamped[0] * T
    # At rest the solid sits 0.16 % below Euler-Bernoulli's 3.5160 (shear, L/h = 20).
    assert at_rest == pytest.approx(3.5160, rel=2.5e-3)
    shear = at_rest / 3.5160
    out_of_plane = 2 * math.pi * solve_modes(beam(90.0, cell=cell), rpm, 1, False).f_undamped[0] * T
    assert out_of_plane / shear == pytest.approx(published, rel=5e-4)
    in_plane = 2 * math.pi * solve_modes(beam(0.0, cell=cell), rpm, 1, False).f_undamped[0] * T
    assert in_plane / shear == pytest.approx(math.sqrt(published**2 - gamma**2), rel=5e-4)


def test_coriolis_ritz_matches_state_space_arnoldi():
    """The Ritz gyroscopic modes against scipy eigs on the full [[0, I], [-K, -G]] z = lambda [[I, 0], [0, M]] z."""
    from reference_fe.modal import solve_modes
    params = beam(30.0, size=0.005)
    rpm = 20000.0
    modes = solve_modes(params, rpm, n_modes=4, coriolis=True)
    free = modes.operators.free()
    K, G, M = free.K.tocsc(), free.G.tocsc(), free.M.tocsc()
    n = free.n
    lu = spla.splu(K)

    def inverse_times_b(y):          # z = A^{-1} B y
        y1, y2 = y[:n], y[n:]
        return np.concatenate([-lu.solve(M @ y2 + G @ y1), y1])

    op = spla.LinearOperator((2 * n, 2 * n), matvec=inverse_times_b, dtype=float)
    mu = spla.eigs(op, k=8, which="LM", return_eigenvectors=False, tol=1e-12)
    lam = 1.0 / mu
    second = np.sort(lam.imag[lam.imag > 0]) / (2 * np.pi)
    assert np.allclose(np.sort(modes.f_coriolis), second[:4], rtol=1e-7)
    assert np.all(np.abs(lam.real) < 1e-6 * np.abs(lam))      # gyroscopic: no damping
    assert np.all(np.abs(modes.damping_coriolis) < 1e-6)        # ... and so says the Ritz lambda
    assert len(set(modes.f_coriolis)) == 4                      # one gyroscopic mode per undamped one
    # The in-plane bending mode is softened by Coriolis coupling to axial motion.
    assert np.any(np.abs(modes.coriolis_shift) > 1e-4)


@pytest.mark.slow
def test_mesh_convergence_towards_exact():
    """Errors against the exact Timoshenko value shrink at least as h^2 (P2 theory: h^4)."""
    from reference_fe.modal import solve_modes
    exact = timoshenko_cantilever(H, B, 0.0, 2)[1]
    sizes = np.array([0.005, 0.0035, 0.0025])
    errors = np.array([abs(solve_modes(beam(90.0, size), 0.0, 3, False).f_undamped[2] - exact)
                       for size in sizes])
    assert np.all(np.diff(errors) < 0), errors
    order = np.log(errors[0] / errors[2]) / np.log(sizes[0] / sizes[2])
    assert order > 2.0, (errors, order)


@pytest.mark.slow
def test_default_blade_first_frequency_matches_paper_fe():
    """Paper Table 1 FE column: 282.4 Hz at 8500 r/min (flap, the beam restrains torsion)."""
    from reference_fe.modal import modal_analysis
    result = modal_analysis(Parameters(), rpm=8500.0, n_modes=4, coriolis=True)
    assert result.modes[0].label == "flap1"
    assert result.modes[0].f_hz == pytest.approx(282.4, rel=0.01)
    assert "torsion1" in result.by_label()


@pytest.mark.slow
@pytest.mark.mpi
def test_mpirun_two_ranks_matches_serial(tmp_path):
    mpirun = Path(sys.executable).parent / "mpirun"
    shroud = Path(sys.executable).parent / "shroud"
    if not mpirun.exists() or not shroud.exists():
        pytest.skip("mpirun or the shroud command is not installed in this environment")
    args = ["modal", "--model", "fe", "--json", "--modes", "4", "--rpm", "12000",
            "--set", "blade.length=0.1", "--set", "fe.mesh_size=0.0035", "--set", "fe.cell=tet"]
    env = dict(os.environ, SHROUD_CACHE=str(tmp_path))
    serial = subprocess.run([str(shroud), *args], capture_output=True, text=True, env=env, check=True)
    parallel = subprocess.run([str(mpirun), "-n", "2", str(shroud), *args], capture_output=True,
                              text=True, env=env, check=True, timeout=600)
    one, two = json.loads(serial.stdout), json.loads(parallel.stdout)
    assert one["dofs"] == two["dofs"]
    assert [m["label"] for m in one["modes"]] == [m["label"] for m in two["modes"]]
    assert np.allclose([m["f_hz"] for m in one["modes"]], [m["f_hz"] for m in two["modes"]], rtol=1e-8)

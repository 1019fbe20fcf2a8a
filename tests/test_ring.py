"""The ring of N blades coupled through their shrouds (geometry.md, "Moving neighbours"), in time.

Truths: the paper's single blade (a ring blade whose neighbours are held
still), the assembled linear ring's frequency response (a stuck ring is
linear; average-acceleration Newmark's steady state is the exact response
at the warped frequency (2/dt) tan(omega dt / 2)), and energy conservation.
"""

import math

import numpy as np
import pytest

from shroud.analysis.api import build_system, transient
from shroud.analysis.ring import build_ring, run_ring
from shroud.analysis.transient import run
from workbench.cli import main
from shroud.base.errors import InputError
from shroud.params import Parameters


# --- parameters ------------------------------------------------------------------------------------

def test_ring_keys_default_to_the_papers_blade():
    r = Parameters().ring
    assert (r.blades, r.mistuning, r.mistuning_std, r.seed) == (0, (), 0.0, 0)
    p = Parameters().with_overrides(["ring.blades=3", "ring.mistuning=[0.01, -0.02, 0]"])
    assert p.ring.deviations == (0.01, -0.02, 0.0) and not p.ring.tuned
    drawn = Parameters().with_overrides(["ring.blades=400", "ring.mistuning_std=0.03", "ring.seed=7"]).ring
    assert np.std(drawn.deviations) == pytest.approx(0.03, rel=0.15)      # 400 draws: within 4 sigma
    assert Parameters().with_overrides(["ring.blades=5"]).ring.deviations == (0.0,) * 5


def _seed_with_a_blade_below(std: float, blades: int) -> int:
    return next(s for s in range(1000) if np.random.default_rng(s).normal(0.0, std, blades).min() <= -1.0)


@pytest.mark.parametrize("assignments, key", [
    (["ring.blades=1"], "ring.blades"),
    (["ring.blades=3", "ring.mistuning=0.01,0.02"], "ring.mistuning"),
    (["ring.blades=2", "ring.mistuning=-1.2,0"], "ring.mistuning"),
    (["ring.mistuning=0.1"], "ring.mistuning"),
    (["ring.blades=2", "ring.mistuning=0.1,0", "ring.mistuning_std=0.1"], "ring.mistuning"),
    (["ring.blades=3", "ring.mistuning=a,b,c"], "ring.mistuning"),
])
def test_bad_ring_input_is_one_line_naming_the_key(assignments, key):
    with pytest.raises(InputError) as err:
        Parameters().with_overrides(assignments)
    assert err.value.key == key and "\n" not in err.value.line()


def test_a_scatter_that_makes_some_E_negative_is_refused():
    seed = _seed_with_a_blade_below(0.6, 12)
    with pytest.raises(InputError) as err:
        Parameters().with_overrides(["ring.blades=12", "ring.mistuning_std=0.6", f"ring.seed={seed}"])
    assert err.value.key == "ring.mistuning_std" and "E <= 0" in err.value.line()


@pytest.mark.parametrize("extra", [["--set", "ring.blades=1"],
                                   ["--set", "ring.blades=3", "--set", "ring.mistuning=0.1"],
                                   ["--set", "ring.blades=3", "--model", "fe"],
                                   ["--set", "ring.blades=3", "--set", "contact.enabled=false"]])
def test_bad_ring_input_exits_2_with_one_line(capsys, extra):
    assert main(["transient", "--json", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "ring." in err[0]


def test_no_ring_is_the_papers_model_bit_for_bit(tmp_path):
    short = ["time.periods=5"]
    paper = run(build_system(Parameters().with_overrides(short), "reduced"), Parameters().with_overrides(short))
    zero = Parameters().with_overrides(short + ["ring.blades=0"])
    again = run(build_system(zero, "reduced"), zero)
    for name in ("tip", "normal", "friction", "tangential", "state"):
        assert np.array_equal(getattr(paper, name), getattr(again, name))
    assert "blades" not in transient(zero, "reduced").to_json()


# --- the ring in time ----------------------------------------------------------------------------

@pytest.mark.parametrize("model, contact, blades", [("reduced", "implicit", 3), ("extended", "implicit", 3),
                                                    ("full", "explicit", 3), ("reduced", "implicit", 24),
                                                    ("extended", "implicit", 24)])
def test_a_ring_blade_with_its_neighbours_held_still_is_the_papers_blade(model, contact, blades):
    """Interface 0 with blade 1 still is the paper's side 2; interface N-1 with blade N-1 still its side 1
    (the extended beam: two paired points per face; the full beam with the paper's explicit contact).
    Blade 0 meets interface N-1 through the corner blocks of the ring's cyclic block-tridiagonal
    compliance: with 24 blades (48 and 96 contact coordinates) the implicit step is the cyclic block
    solve's, with 3 the dense one's (ring_newmark.CYCLIC_FROM)."""
    p = Parameters().with_overrides([f"ring.blades={blades}", "time.periods=12", "speed.rpm=9000",
                                     f"time.contact={contact}"])
    ring = run_ring(build_ring(p, model), p, held=tuple(range(1, blades)))
    paper = run(build_system(p, model), p)
    scale_tip, scale_N = np.abs(paper.tip).max(), np.abs(paper.normal).max()
    last = blades - 1
    assert scale_N > 1.0                                   # the contact works, on both sides
    assert np.abs(ring.tip[:, 0] - paper.tip).max() <= 1e-11 * scale_tip
    assert np.abs(ring.normal[:, 0] - paper.normal[:, 1]).max() <= 1e-10 * scale_N
    assert np.abs(ring.normal[:, last] - paper.normal[:, 0]).max() <= 1e-10 * scale_N
    assert np.abs(ring.friction[:, 0] - paper.friction[:, 1]).max() <= 1e-10 * scale_N
    assert np.abs(-ring.friction[:, last] - paper.friction[:, 0]).max() <= 1e-10 * scale_N
    assert np.array_equal(ring.state[:, [last, 0]], paper.state)
    assert np.all(ring.tip[:, 1:] == 0.0)


@pytest.mark.parametrize("blades", [3, 24])
def test_the_cyclic_block_contact_solve_is_the_dense_solve_of_the_rings_compliance(blades):
    """The implicit contact step y = y_pred + Cc lam(y) on a ring of extended beams (two points an
    interface, four coordinates) solved by the cyclic block-tridiagonal factorization and by the dense
    active-set LU: the same y and states to round-off over 400 successive predictors (one workspace
    each, as in a run: the factors are reused and refactored as the states change), separations,
    sticks and slips of both directions among them, and y satisfies the law's equation. Interfaces
    N-1 and 0 (blade 0's two sides) are pressed hardest, so the corner blocks carry the coupling."""
    from shroud.core.contact import evaluate, solve_contact, workspace
    from shroud.core.newmark import NewmarkScheme
    from shroud.core.ring_newmark import factorize
    from shroud.analysis.ring import ring_law
    p = Parameters().with_overrides([f"ring.blades={blades}", "contact.N0=5"])
    ring = build_ring(p, "extended")
    step = factorize(ring, NewmarkScheme(dt=p.time_step))
    law = ring_law(ring, p)
    m, k = law.m, law.count
    rng = np.random.default_rng(blades)
    ws_cyclic, ws_dense = workspace(law, blocks=step.blocks()), workspace(law)
    z_old, seen = np.zeros(k), set()
    press = np.zeros(m)
    press[0:m:2] = 2e-7                                  # normals: into contact around the ring ...
    press[[0, 2, m - 4, m - 2]] = 1e-6                   # ... most at interfaces 0 and N-1
    for i in range(400):
        y_pred = press * (1 + np.sin(0.1 * i)) + 3e-7 * rng.normal(size=m)
        out = []
        for ws in (ws_cyclic, ws_dense):
            y, lam = np.zeros(m), np.zeros(m)
            N, F, z, state = np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k, np.int64)
            it, ok = solve_contact(y_pred, step.Cc, z_old, law.rows, law.props, y, lam, N, F, z, state, ws)
            assert ok
            out.append((y, lam, z, state))
        (y, lam, z, state), (y_d, _, _, state_d) = out
        scale = np.abs(y_pred).max()
        assert np.abs(y - y_d).max() <= 1e-12 * scale
        assert np.array_equal(state, state_d)
        assert np.abs(y - y_pred - step.Cc @ lam).max() <= 1e-12 * scale
        lam2 = np.zeros(m)
        evaluate(y, z_old, law.rows, law.props, lam2, np.zeros(k), np.zeros(k), np.zeros(k), np.zeros(k, np.int64))
        assert np.array_equal(lam, lam2)
        seen |= {(int(s), bool(f > 0)) for s, f in zip(state, F)}
        z_old = z
    assert seen >= {(0, False), (1, True), (1, False), (2, True), (2, False)}


def _assembled_stuck_ring(p: Parameters):
    """M, C, K of N copies of the blade, the relative projection built from the blade's shroud rows
    (g_j = v_s,j - v_s,j+1, r_j = w_s,j - w_s,j+1), the travelling-wave load's complex amplitude."""
    blade = build_system(p, "reduced")
    N, ke = p.ring.blades, p.load.ke
    P = blade.contact.W[[0, 1]]                           # the point shroud: (v_s, w_s) at the tip
    shift = np.roll(np.eye(N), 1, axis=1)                  # (shift q)_j = q_j+1
    Wn, Wt = np.kron(np.eye(N) - shift, P[:1]), np.kron(np.eye(N) - shift, P[1:])
    M, C, K = (np.kron(np.eye(N), A) for A in (blade.M, blade.C, blade.K))
    F = np.kron(np.exp(1j * 2 * math.pi * ke * np.arange(N) / N), blade.f_aero)   # f_j = Im(F_j e^{i w t})
    return blade, M, C, K, Wn, Wt, F, np.kron(np.ones(N), blade.f_const)


def test_a_stuck_linear_ring_follows_the_assembled_rings_frequency_response():
    """A preload and mu so large that every interface sticks: the ring is linear with springs kn, kt on
    g, r. Started on its steady state, it stays there, blade by blade, step by step."""
    p = Parameters().with_overrides(["ring.blades=5", "load.ke=3", "contact.N0=1000", "contact.mu=1000",
                                     "time.periods=4", "speed.rpm=8000"])
    kn, kt, N0 = p.contact.kn, p.contact.kt, p.contact.N0
    blade, M, C, K, Wn, Wt, F, f_const = _assembled_stuck_ring(p)
    K_stuck = K + kn * Wn.T @ Wn + kt * Wt.T @ Wt
    dt, w = p.time_step, blade.omega_e
    sigma = 2j / dt * math.tan(w * dt / 2)                 # Newmark's steady state: s -> (2/dt) tan(w dt/2)
    X = np.linalg.solve(sigma**2 * M + sigma * C + K_stuck, F)
    # the sliders start at r(0): their springs hold r about it, a constant force kt Wt^T r(0);
    # the preload's -N0 cancels around a tuned ring (Wn^T 1 = 0)
    q_s = np.linalg.solve(K + kn * Wn.T @ Wn, f_const - N0 * Wn.T @ np.ones(Wn.shape[0])
                          + kt * Wt.T @ (Wt @ X.imag))
    nb = blade.dofs
    shape = (p.ring.blades, nb)
    tr = run_ring(build_ring(p, "reduced"), p, q0=(q_s + X.imag).reshape(shape),
                  v0=(sigma * X).imag.reshape(shape), a0=(sigma**2 * X).imag.reshape(shape))
    assert np.all(tr.state == 1)                           # stuck throughout
    n = np.arange(tr.steps + 1)
    q = q_s[None, :] + (X[None, :] * np.exp(1j * w * dt * n)[:, None]).imag
    expected = np.einsum("cb,njb->njc", blade.tip, q.reshape(-1, *shape))
    scale = np.abs(expected - expected.mean(axis=0)).max()
    assert np.abs(tr.tip - expected).max() <= 1e-9 * scale


def test_the_rings_energy_balance_closes_with_friction_and_mistuning():
    """Preloaded, slipping, mistuned: the load's work goes into damping, friction and stored energy to
    round-off (no impact kink: no point separates)."""
    p = Parameters().with_overrides(["ring.blades=4", "ring.mistuning=0.02,-0.03,0.01,0", "contact.N0=20",
                                     "contact.mu=0.05", "time.periods=40", "load.ke=1"])
    tr = run_ring(build_ring(p, "reduced"), p)
    e = tr.energy
    assert np.all(tr.state > 0) and np.any(tr.state == 2)
    assert e.friction > 0.05 * e.input_work
    assert e.relative_error < 1e-9


def test_a_ring_too_long_to_record_is_refused_before_it_starts(capsys):
    """48 blades record 48 x 41 bytes a step, 13 times a single blade's 154: a run the single blade could
    record but the ring cannot is refused (one line, exit 2)."""
    from shroud.analysis.checks import MEMORY_SHARE
    from shroud.base.resources import physical_memory
    periods = int(MEMORY_SHARE * physical_memory() / (256 * 600))      # 154 < 600 < 48 x 41 bytes a step
    assert main(["transient", "--json", "--set", "ring.blades=48", "--set", f"time.periods={periods}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "time.periods" in err[0]

"""The cyclic sector of blade and flexible disk (reference_fe.cyclic, docs/disk.md) against the whole ring
it stands for, and in the rigid-disk limit against the clamped blade.

The whole ring is N copies of the sector's assembled matrices, copy j turned by 2 pi j / N about Z
and glued node to node (its side +pi/N onto copy j+1's side -pi/N), bore clamped, with its own
centrifugal state solved on the whole ring and each copy's geometric stiffness assembled from it: no
cyclic constraint anywhere. Its frequencies are the sector's of every nodal diameter together (k and
N - k twice), which the sector must give to the eigen-solvers' tolerance, with the shroud interfaces
free and stuck (springs joining each copy's side 2 to the next copy's side 1).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytestmark = pytest.mark.fe

COARSE = {"ring.blades": 4, "disk.thickness": 0.04, "fe.cell": "tet", "fe.mesh_size": 0.0035, "fe.order": 1}


def _whole_ring(sec, rpm: float, stuck: tuple[float, float] | None):
    """(K, M) of the N-sector ring on its unclamped DOFs, scipy CSR, in the global frame; ``stuck`` (kn, kt):
    springs between copy j's side-2 contact nodes and copy j+1's side-1 nodes, on their own-frame
    displacements along e_vs and e_ws, kn and kt per face by the nodes' area shares."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
    from dolfinx import fem
    from meshes.disk import rotation_z
    from reference_fe.cyclic import rotation_stiffness
    N, n = sec.model.spec.blades, sec.M.shape[0]
    nodes = n // 3
    ring_node = np.arange(N)[:, None] * nodes + np.arange(nodes)[None, :]      # (N, nodes)
    for j in range(N):
        ring_node[j, sec.high] = ((j + 1) % N) * nodes + sec.low                 # glued to the next copy
    bore = np.zeros(N * nodes, dtype=bool)
    bore[(np.arange(N)[:, None] * nodes + np.unique(sec.clamped // 3)[None, :]).ravel()] = True
    used = np.unique(ring_node)
    free_nodes = used[~bore[used]]
    number = np.full(N * nodes, -1)
    number[free_nodes] = np.arange(free_nodes.size)
    size = 3 * free_nodes.size
    P = []                                # u_copy_j (its own frame) = P_j u_ring
    for j in range(N):
        R = rotation_z(2 * math.pi * j / N)
        rows, cols, vals = [], [], []
        for i in range(nodes):
            g = number[ring_node[j, i]]
            if g < 0:
                continue
            for a in range(3):
                for b in range(3):
                    rows.append(3 * i + a)
                    cols.append(3 * g + b)
                    vals.append(R[b, a])          # R^T: global -> the copy's frame
        P.append(sp.csr_matrix((vals, (rows, cols)), shape=(n, size)))
    assemble = lambda mats: sum((Pj.T @ A @ Pj for Pj, A in zip(P, mats)), sp.csr_matrix((size, size)))
    K_e = assemble([sec.K_e] * N).tocsc()
    u_ring = spla.spsolve(K_e, sum(Pj.T @ sec.f_c1 for Pj in P))
    omega2 = (2 * math.pi * rpm / 60) ** 2
    K_rot = []
    for Pj in P:                          # each copy's geometric stiffness from the ring's own state
        u0 = fem.Function(sec.model.V)
        u0.x.array[:] = Pj @ u_ring
        K_rot.append(rotation_stiffness(sec.model, sec.stiffness, u0))
    K = K_e + omega2 * assemble(K_rot)
    if stuck is not None:
        pairs = sec.contact
        D = sp.diags(np.ravel(np.column_stack([stuck[0] * pairs.weight, stuck[1] * pairs.weight])))
        for j in range(N):
            E = sp.kron(sp.eye(pairs.weight.size), sp.csr_matrix(pairs.directions))     # (2P, 3P)
            y = E @ (P[j][pairs.side2.ravel()] - P[(j + 1) % N][pairs.side1.ravel()])   # (2P, ring DOFs)
            K = K + y.T @ D @ y
    return K.tocsc(), assemble([sec.M] * N).tocsc()


@pytest.mark.parametrize("interface", ["free", "stuck"])
def test_four_sectors_glued_have_the_sectors_frequencies(interface):
    import scipy.sparse.linalg as spla
    from reference_fe.cyclic import diameter_modes, sector
    from shroud.params import Parameters
    rpm = 10000.0
    params = Parameters().updated(COARSE)
    sec = sector(params)
    stuck = (params.contact.kn, params.contact.kt) if interface == "stuck" else None
    per_k = [diameter_modes(sec, rpm, k, 6, coriolis=False, stuck=stuck).f_hz for k in (0, 1, 2)]
    cutoff = min(f[-1] for f in per_k)
    union = np.sort(np.concatenate([per_k[0], per_k[1], per_k[1], per_k[2]]))   # k = 3 mirrors k = 1
    expected = union[union < cutoff * (1 - 1e-6)]
    K, M = _whole_ring(sec, rpm, stuck)
    w2 = np.sort(spla.eigsh(K, k=expected.size + 1, M=M, sigma=0.0, which="LM", tol=1e-12)[0])
    ring = np.sqrt(w2) / (2 * math.pi)
    np.testing.assert_allclose(ring[:expected.size], expected, rtol=1e-8, atol=0)
    assert ring[expected.size] > expected[-1] * (1 + 1e-6)       # no ring mode the sector missed


@pytest.mark.slow
def test_rigid_disk_limit_is_the_clamped_blade():
    """With the disk's E x 1000 every nodal diameter's modes are the blade's clamped at its root, to
    0.5 %: what is left is the blade between the curved rim and the plane root X = R_d (0.56 mm at the
    chord edges, the 24-blade sector; docs/disk.md), and the two meshes' difference."""
    from reference_fe.cyclic import diameter_modes, sector
    from reference_fe.modal import solve_modes
    from shroud.params import Parameters
    tets = {"fe.cell": "tet", "fe.mesh_size": 0.0035, "fe.order": 2}
    rpm = 10000.0
    clamped = solve_modes(Parameters().updated(tets), rpm, 6, coriolis=False)
    sec = sector(Parameters().updated({**tets, "ring.blades": 24, "disk.thickness": 0.04, "disk.E_factor": 1000.0}))
    for k in (0, 1, 12):
        found = diameter_modes(sec, rpm, k, 6, coriolis=False)
        assert found.labels == clamped.labels
        np.testing.assert_allclose(found.f_hz, clamped.f_undamped, rtol=5e-3)


# The converged reference at rest (docs/disk.md, "(d) amended": P3 on three sectors graded towards the rim
# edge, Richardson in the edge size; `python scripts/disk_checks.py reference`): per nodal diameter and mode,
# (limit in Hz, its own error in %: the step from the finest mesh plus the far field's).
CONVERGED_AT_REST = {
    0: {"flap1": (196.955, 0.036), "chord1": (821.394, 0.068), "flap2": (1237.231, 0.029),
        "torsion1": (1530.265, 0.028), "chord2": (2683.520, 0.018), "flap3": (3063.866, 0.007)},
    12: {"flap1": (197.757, 0.037), "chord1": (986.571, 0.121), "flap2": (1303.070, 0.029),
         "torsion1": (1530.369, 0.028), "flap3": (3554.169, 0.031), "torsion2": (4795.997, 0.021)}}


def test_default_sector_is_within_half_a_percent_of_the_converged_reference():
    """Issue 35's accuracy at rest, where the rim edge costs most: the default sector (24 blades, P2 3.5 mm,
    graded at the rim edge) has each of its six modes at k = 0 and 12 within 0.5 % of the converged P3
    limit, decided (error below 0.5 % less the limit's own error). The uniform mesh fails it (flap1 0.556 %
    at k = 0), as would a grading lost from meshes.disk."""
    from reference_fe.cyclic import diameter_modes, sector
    from shroud.params import Parameters
    sec = sector(Parameters().updated({"fe.cell": "tet", "fe.mesh_size": 0.0035, "fe.order": 2,
                                       "ring.blades": 24, "disk.thickness": 0.04}))
    for k, reference in CONVERGED_AT_REST.items():
        found = diameter_modes(sec, 0.0, k, 6, coriolis=False)
        assert sorted(found.labels) == sorted(reference)
        for label, f in zip(found.labels, found.f_hz):
            limit, own = reference[label]
            assert 100 * abs(f / limit - 1) < 0.5 - own, (k, label, f, limit)

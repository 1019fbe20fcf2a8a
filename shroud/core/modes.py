"""Mode labels from tip kinematics, and the modal assurance criterion.

Both models (beam and solid) name a mode by how its tip moves: ``flap``
(along e_v(L), the thickness direction), ``chord`` (along e_w(L)),
``torsion`` (rotation about X times a length scale), ``axial`` (along X).
Labels are numbered in frequency order within each kind: flap1, chord1,
flap2, ... (docs/interface.md).
"""

from __future__ import annotations

import numpy as np

KINDS = ("flap", "chord", "torsion", "axial")


def participation(components: np.ndarray) -> np.ndarray:
    """(k, 4) shares of the squared tip motion by kind; rows sum to 1 (0 for a still tip)."""
    c2 = np.abs(np.asarray(components, dtype=complex)) ** 2
    total = c2.sum(axis=1, keepdims=True)
    return np.divide(c2, total, out=np.zeros_like(c2, dtype=float), where=total > 0)


def label_modes(components: np.ndarray) -> tuple[list[str], list[dict[str, float]]]:
    """Labels and participation shares of modes given in frequency order.

    ``components`` is (k, 4): tip-motion magnitudes [flap, chord, torsion,
    axial] per mode, in any one consistent unit (m, or rad x a length). A mode
    takes the kind with the largest share.

    >>> label_modes(np.array([[1.0, 0.1, 0, 0], [0.2, 1.0, 0, 0], [1.0, 0.0, 0, 0]]))[0]
    ['flap1', 'chord1', 'flap2']
    """
    shares = participation(components)
    count = dict.fromkeys(KINDS, 0)
    labels, parts = [], []
    for row in shares:
        kind = KINDS[int(np.argmax(row))]
        count[kind] += 1
        labels.append(f"{kind}{count[kind]}")
        parts.append({k: round(float(v), 4) for k, v in zip(KINDS, row)})
    return labels, parts


def mac(phi_a: np.ndarray, phi_b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion |a^H b|^2 / ((a^H a)(b^H b)) between columns.

    ``phi_a`` (n, ka) and ``phi_b`` (n, kb), real or complex; returns (ka, kb)
    values in [0, 1] (1: the same shape up to scale and phase).
    """
    a = np.asarray(phi_a).reshape(len(phi_a), -1)
    b = np.asarray(phi_b).reshape(len(phi_b), -1)
    cross = np.abs(a.conj().T @ b) ** 2
    norms = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return cross / norms


def pair_by_mac(macs: np.ndarray) -> np.ndarray:
    """One-to-one pairing of the rows of a MAC matrix with its columns, largest total MAC.

    ``macs`` (ka, kb), ka <= kb: returns for each row the column paired with
    it, no column twice (an optimal assignment; a per-row argmax can give
    two modes the same partner).

    >>> pair_by_mac(np.array([[0.9, 0.8], [0.7, 0.1]]))      # argmax would pair both rows with column 0
    array([1, 0])
    """
    best = np.argmax(macs, axis=1)
    if len(np.unique(best)) == len(best):    # each row's best, no column twice: the sum of the row
        return best                           # maxima bounds every assignment, so this one is optimal
    from scipy.optimize import linear_sum_assignment     # scipy.optimize costs 0.3 s to import
    rows, cols = linear_sum_assignment(-np.asarray(macs))
    return cols[np.argsort(rows)]

"""Campbell tracking and excitation-line crossings of the beam model."""

import numpy as np
import pytest

from reduced_model.campbell import campbell
from reduced_model.modal import modal_analysis
from shroud.params import Parameters


def test_tracks_keep_their_labels_and_crossing_is_a_resonance():
    params = Parameters()
    rpms = np.linspace(0.0, 15000.0, 60)
    result = campbell(params, rpms, n_modes=4, coriolis=True)
    assert result.labels == ("flap1", "chord1", "flap2", "flap3")
    for i in (0, 25, 59):       # a track is the mode with its label at every speed, not an index
        f = modal_analysis(params, rpm=rpms[i], n_modes=6, coriolis=True).by_label()
        np.testing.assert_allclose(result.f_hz[i], [f[lab] for lab in result.labels], rtol=1e-9)
    (label, rpm, f_cross), = result.crossings(2)
    assert label == "flap1"
    exact = modal_analysis(params, rpm=rpm, n_modes=1, coriolis=True).modes[0].f_hz
    assert exact == pytest.approx(2 * rpm / 60, rel=2e-4)        # linear interpolation error only


def test_centrifugal_stiffening_raises_flap1_monotonically():
    result = campbell(Parameters(), np.linspace(0.0, 15000.0, 30), n_modes=2, coriolis=False)
    assert np.all(np.diff(result.f_hz[:, 0]) > 0)

"""Steady-state measures of a sampled response (paper Sect. 3, Figs. 4 and 11-15).

All functions take a signal sampled ``steps_per_period`` times per excitation
period (the Newmark step, dt = T_e / steps_per_period) with the last sample at
the end of a whole period, as shroud.core.newmark records it.
"""

from __future__ import annotations

import numpy as np

from shroud.core.states import STATE_NAMES

STEADY_PERIODS = 10        # amplitudes, peaks and state fractions: the last 10 periods


def last_periods(x: np.ndarray, steps_per_period: int, periods: int = STEADY_PERIODS) -> np.ndarray:
    """The samples of the last ``periods`` excitation periods (whole periods, end included)."""
    n = min(len(x) - 1, periods * steps_per_period)
    return np.asarray(x)[len(x) - 1 - n:]


def amplitude(x: np.ndarray, steps_per_period: int, periods: int = STEADY_PERIODS) -> float:
    """Steady-state amplitude (max - min) / 2 over the last ``periods`` periods (units of x).

    Examples
    --------
    A decaying transient on a sine of amplitude 2: only the last periods count.

    >>> t = np.arange(64 * 40 + 1) / 64                     # 40 periods, 64 samples each
    >>> x = 2 * np.sin(2 * np.pi * t) + 5 * np.exp(-t)
    >>> round(amplitude(x, 64), 6)
    2.0
    """
    w = last_periods(x, steps_per_period, periods)
    return 0.5 * float(w.max() - w.min())


def poincare(x: np.ndarray, steps_per_period: int) -> np.ndarray:
    """One sample per excitation period, at the phase of the last sample (oldest first)."""
    return np.asarray(x)[::-1][::steps_per_period][::-1]


def detect_period(x: np.ndarray, steps_per_period: int, max_period: int = 10,
                  rtol: float = 2e-3, window: int = 30) -> int | None:
    """Period of the response in excitation periods (1 = P1, ..., 10 = P10), or None.

    The Poincare samples (once per excitation period) of the last ``window``
    periods repeat with the smallest p for which every sample equals the one
    p periods earlier, to ``rtol`` times the signal's peak-to-peak range over
    the window. At least two repetitions of the candidate period are required.
    None: no period up to ``max_period`` (quasi-periodic, chaotic, or still
    in its transient).

    Examples
    --------
    A response with a subharmonic at a third of the excitation frequency is P3:

    >>> t = np.arange(32 * 40 + 1) / 32
    >>> detect_period(np.sin(2 * np.pi * t) + 0.3 * np.sin(2 * np.pi * t / 3), 32)
    3
    >>> detect_period(np.sin(2 * np.pi * t) + 0.3 * np.sin(2 * np.pi * t / np.sqrt(2)), 32) is None
    True
    """
    tail = last_periods(x, steps_per_period, window)
    scale = float(tail.max() - tail.min())
    samples = poincare(tail, steps_per_period)
    if scale == 0.0:
        return 1
    for p in range(1, max_period + 1):
        if len(samples) < 2 * p + 1:
            return None
        if np.max(np.abs(samples[p:] - samples[:-p])) <= rtol * scale:
            return p
    return None


def spectrum(x: np.ndarray, dt: float, steps_per_period: int, periods: int = STEADY_PERIODS):
    """One-sided amplitude spectrum of the last ``periods`` periods: (f in Hz, amplitude).

    A whole number of excitation periods leaks nothing at the excitation
    harmonics; the mean is removed. Amplitude in units of x (a sine of
    amplitude A shows A at its frequency).
    """
    w = last_periods(x, steps_per_period, periods)[1:]
    w = w - w.mean()
    amp = np.abs(np.fft.rfft(w)) * 2.0 / len(w)
    amp[0] /= 2.0
    return np.fft.rfftfreq(len(w), dt), amp


def state_fractions(states: np.ndarray, steps_per_period: int,
                    periods: int = STEADY_PERIODS) -> dict[str, float]:
    """Share of the last ``periods`` periods spent separate / stick / slip."""
    w = last_periods(states, steps_per_period, periods)[1:]
    return {name: float(np.mean(w == code)) for code, name in enumerate(STATE_NAMES)}


def peak(x: np.ndarray, steps_per_period: int, periods: int = STEADY_PERIODS) -> float:
    """Largest |x| over the last ``periods`` periods."""
    return float(np.max(np.abs(last_periods(x, steps_per_period, periods))))

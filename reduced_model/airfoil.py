"""The blade's cross-section along the span: the paper's rectangle or a NACA four-digit profile, tapered.

shared/spec/geometry.md, "Airfoil blades and the user's own CAD":
* chord c(x) and maximum thickness t(x) linear from root (x = 0) to tip
  (x = L): c(0) = blade.width, c(L) = blade.width * blade.chord_taper, t(0) =
  blade.thickness, t(L) = blade.thickness * blade.thickness_taper, m;
* the NACA profile in chord fractions s in [0, 1] from the leading edge:
  camber y_c(s) = m / p^2 (2 p s - s^2) for s < p, m / (1 - p)^2 ((1 - 2 p) +
  2 p s - s^2) for s >= p; half-thickness y_t(s) = 5 tau (0.2969 sqrt(s) -
  0.1260 s - 0.3516 s^2 + 0.2843 s^3 - 0.1036 s^4) (the closed trailing edge:
  y_t(1) = 0), tau = t(x) / c(x); surfaces (s -/+ y_t sin theta, y_c +/- y_t cos
  theta), theta = atan(dy_c/ds);
* in the section frame the chord runs along e_w with the leading edge towards
  -e_w and the camber towards +e_v, the area centroid at the origin (the
  sections are stacked on their centroids).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from shroud.params import Blade, Shroud
from reduced_model.section import SectionProperties, rectangle
from reduced_model.section_mesh import section_on_mesh
from reduced_model.step_slices import sliced_blade

PROFILE_POINTS = 240          # points along each surface, cosine-spaced (dense at both edges)
MESH_CELLS_THICK = 16         # P2 triangles' size: the profile's maximum thickness over this


def naca4_camber(m: float, p: float, s) -> tuple[np.ndarray, np.ndarray]:
    """The camber line y_c(s) (chord units) and its slope dy_c/ds at chord fractions ``s``."""
    s = np.asarray(s, dtype=float)
    if m == 0:
        return np.zeros_like(s), np.zeros_like(s)
    front = s < p
    return (np.where(front, m / p**2 * (2 * p * s - s**2), m / (1 - p) ** 2 * ((1 - 2 * p) + 2 * p * s - s**2)),
            np.where(front, 2 * m / p**2 * (p - s), 2 * m / (1 - p) ** 2 * (p - s)))


def naca4_half_thickness(tau, s):
    """y_t(s), chord units, at chord fractions ``s`` of a profile tau thick (numpy or UFL arguments)."""
    return 5 * tau * (0.2969 * s**0.5 - 0.1260 * s - 0.3516 * s**2 + 0.2843 * s**3 - 0.1036 * s**4)


def naca4_points(m: float, p: float, tau: float, s, r) -> np.ndarray:
    """Points (s_c, y) in chord units at chord fraction ``s``, ``r`` half-thicknesses off the camber line
    along its normal: the upper surface at r = +1, the lower at r = -1 (arrays broadcast), shape (..., 2)."""
    s = np.asarray(s, dtype=float)
    y_c, slope = naca4_camber(m, p, s)
    y_t = naca4_half_thickness(tau, s)
    theta = np.arctan(slope)
    return np.stack(np.broadcast_arrays(s - r * y_t * np.sin(theta), y_c + r * y_t * np.cos(theta)), axis=-1)


def naca4_surfaces(m: float, p: float, tau: float, s: np.ndarray):
    """Upper and lower surfaces (s, y) in chord units at chord fractions ``s``: two (n, 2) arrays."""
    return naca4_points(m, p, tau, s, 1.0), naca4_points(m, p, tau, s, -1.0)


def polygon_centroid(loop: np.ndarray) -> np.ndarray:
    """Area centroid of a simple polygon (n, 2) (Green's theorem)."""
    a, b = loop, np.roll(loop, -1, axis=0)
    cross = a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]
    return np.sum((a + b) * cross[:, None], axis=0) / (3.0 * np.sum(cross))


def _chordwise_loop(m: float, p: float, tau: float, points: int) -> np.ndarray:
    """The profile's polygon (s, y), chord units: upper surface from the trailing edge to the leading edge,
    then the lower one back, ``points`` per surface cosine-spaced (dense at both edges), edges shared once."""
    s = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, points)))
    upper, lower = naca4_surfaces(m, p, tau, s)
    return np.concatenate([upper[::-1], lower[1:-1]])


def naca4_centroid(m: float, p: float, tau: float, points: int = PROFILE_POINTS) -> np.ndarray:
    """(s, y) of the area centroid of the profile's polygon of ``points`` per surface, chord units: the
    point every section is stacked on (naca4_outline)."""
    return polygon_centroid(_chordwise_loop(m, p, tau, points))


def naca4_outline(m: float, p: float, tau: float, chord: float, points: int = PROFILE_POINTS) -> np.ndarray:
    """The profile as a polygon (eta_v, eta_w), m, in the section frame, its area centroid at the origin.

    Upper surface from the trailing edge to the leading edge, then the lower
    one back; ``points`` per surface.
    """
    loop = _naca4_loop(m, p, tau, chord, points)
    return loop - polygon_centroid(loop)


def _naca4_loop(m: float, p: float, tau: float, chord: float, points: int) -> np.ndarray:
    """naca4_outline before it is centred: (eta_v, eta_w) = c (y, s_c), the leading edge at the origin."""
    return chord * _chordwise_loop(m, p, tau, points)[:, ::-1]      # (eta_v, eta_w) = c (y, s)


def naca4_place(m: float, p: float, tau: float, chord: float, points: int, s, r) -> np.ndarray:
    """(eta_v, eta_w), m, of the points (s, r) of naca4_points in the frame of naca4_outline(.., points)
    (its polygon's centroid at the origin): what carries a point of one section to the same (s, r) of
    another, shape (..., 2)."""
    return chord * naca4_points(m, p, tau, s, r)[..., ::-1] - polygon_centroid(_naca4_loop(m, p, tau, chord, points))


def naca4_coordinates(m: float, p: float, tau: float, chord: float, points: int, eta: np.ndarray):
    """The inverse of naca4_place: (s, r) of points ``eta`` (n, 2) (eta_v, eta_w), m, inside the profile.

    s is the foot of the point's normal on the camber line (the root of (S - s) + (Y - y_c(s)) y_c'(s),
    decreasing in s for a point within the profile's half-thickness of a camber line whose slope varies
    as slowly as a NACA four-digit one's), r its distance along that normal over y_t(s); r = 0 where
    y_t(s) vanishes (the edges, where every r is the same point).
    """
    c_eta = (np.asarray(eta, dtype=float) + polygon_centroid(_naca4_loop(m, p, tau, chord, points))) / chord
    Y, S = c_eta[:, 0], c_eta[:, 1]

    def foot(s):                         # (S - s, Y - y_c) . (1, y_c')
        y_c, slope = naca4_camber(m, p, s)
        return (S - s) + (Y - y_c) * slope

    lo, hi = np.zeros_like(S), np.ones_like(S)
    for _ in range(60):                  # bisection to 1e-18 of the chord
        mid = 0.5 * (lo + hi)
        right = foot(mid) > 0
        lo, hi = np.where(right, mid, lo), np.where(right, hi, mid)
    s = 0.5 * (lo + hi)
    camber, upper = naca4_points(m, p, tau, s, 0.0), naca4_points(m, p, tau, s, 1.0)
    normal = upper - camber
    half = np.einsum("ij,ij->i", normal, normal)
    r = np.divide(np.einsum("ij,ij->i", c_eta[:, ::-1] - camber, normal), half, out=np.zeros_like(S),
                  where=half > 1e-24)
    return s, r


def chord_and_thickness(blade: Blade, x: float) -> tuple[float, float]:
    """(c(x), t(x)), m, at x m from the root: linear between root and tip values."""
    share = x / blade.length
    return (blade.width * (1.0 + (blade.chord_taper - 1.0) * share),
            blade.thickness * (1.0 + (blade.thickness_taper - 1.0) * share))


@functools.lru_cache(maxsize=64)
def _naca4_section(m: float, p: float, tau: float, chord: float) -> SectionProperties:
    return section_on_mesh(naca4_outline(m, p, tau, chord), size=tau * chord / MESH_CELLS_THICK)


def blade_section(blade: Blade, x: float) -> SectionProperties:
    """The section at x m from the root, in the section frame about its centroid (SI).

    The rectangle by the grid method (what reduced_model.beam takes), the
    NACA profile by P2 triangles on its outline (reduced_model.section_mesh).
    """
    chord, thickness = chord_and_thickness(blade, x)
    if blade.section == "naca4":
        return _naca4_section(blade.naca_m, blade.naca_p, thickness / chord, chord)
    return rectangle(chord, thickness)


SPAN_STATIONS = 4             # sections solved along a span whose profile changes shape (docs/extended-beam.md)
# how each property scales with chord c and thickness t for a profile of fixed shape (thin-section laws)
_SCALING = {"area": (1, 1), "I_v": (1, 3), "I_w": (3, 1), "I_vw": (3, 1), "I_rr": (5, 1), "I_rrv": (4, 1),
            "I_rrw": (4, 1), "J": (1, 3), "warping": (3, 3), "shear_v": (1, 0), "shear_w": (1, 0),
            "kappa_v": (0, 0), "kappa_w": (0, 0)}


@dataclass(frozen=True)
class SpanSections:
    """Section properties at points x along the span, each an array like x; SI.

    About the centroid in the section frame (e_v, e_w): area A (m^2), I_v =
    int eta_v^2 dA, I_w, I_vw (m^4), I_rr = int r^4 dA (m^6), I_rrv = int r^2
    eta_v dA and I_rrw (m^5), J (m^4), the warping constant about the shear
    centre (m^6), the shear centre's offset (shear_v, shear_w) from the
    centroid (m), Cowper's shear coefficients along the principal axes
    nearest e_v and e_w (None when not asked for).
    """

    area: np.ndarray
    I_v: np.ndarray
    I_w: np.ndarray
    I_vw: np.ndarray
    I_rr: np.ndarray
    I_rrv: np.ndarray
    I_rrw: np.ndarray
    J: np.ndarray
    warping: np.ndarray
    shear_v: np.ndarray
    shear_w: np.ndarray
    kappa_v: np.ndarray | None = None
    kappa_w: np.ndarray | None = None


def _station_values(section: SectionProperties, nu: float | None) -> dict:
    cv, cw = section.centroid
    sv, sw = section.shear_centre
    kappa = section.shear_coefficients(nu) if nu is not None else (None, None)
    return dict(area=section.area, I_v=section.I_v, I_w=section.I_w, I_vw=section.I_vw, I_rr=section.I_rr,
                I_rrv=section.I_rrv, I_rrw=section.I_rrw, J=section.J, warping=section.warping,
                shear_v=sv - cv, shear_w=sw - cw,
                kappa_v=kappa[0], kappa_w=kappa[1])


def span_stations(blade: Blade, count: int = SPAN_STATIONS) -> np.ndarray:
    """Where sections are solved, m from the root: the root alone for a profile that keeps its shape
    (chord and thickness tapered alike: every property then scales exactly), otherwise ``count``
    Chebyshev-Lobatto points (root and tip included)."""
    if blade.chord_taper == blade.thickness_taper or count == 1:
        return np.zeros(1)
    return 0.5 * blade.length * (1.0 - np.cos(np.pi * np.arange(count) / (count - 1)))


def span_sections(blade: Blade, x, nu: float | None = None, count: int = SPAN_STATIONS,
                  shroud: Shroud | None = None) -> SpanSections:
    """The sections at ``x`` (m from the root), from the sections solved at stations along the span.

    The stations: span_stations(blade, count) on the blade.* keys' profile,
    or the slices of the STEP file ``blade.step`` (reduced_model.step_slices,
    checked against ``shroud``, the shroud keys), their chord and thickness
    those measured on the slices. Each station's property is carried to x by
    the scaling of a profile of fixed shape, A_k (c(x) / c_k)^a (t(x) /
    t_k)^b (_SCALING), and the stations' values are joined by the Lagrange
    polynomial through them: exact for a profile that keeps its shape, and
    what is left is the slow change of shape with t/c (measured in
    docs/extended-beam.md). c(x), t(x): the keys' linear tapers, or for a
    file the Lagrange polynomial through the slices' values. ``nu``:
    Poisson's ratio for the shear coefficients (None: not solved).
    """
    x = np.asarray(x, dtype=float)
    if blade.step:
        sliced = sliced_blade(blade, shroud)
        stations, sections = sliced.stations, sliced.sections
        scales = np.column_stack([sliced.chords, sliced.thicknesses])
    else:
        stations = span_stations(blade, count)
        sections = [blade_section(blade, float(xk)) for xk in stations]
        scales = np.column_stack(chord_and_thickness(blade, stations))
    weights = np.ones((1,) + x.shape)
    if stations.size > 1:
        weights = np.stack([np.prod([(x - xj) / (xk - xj) for j, xj in enumerate(stations) if j != k], axis=0)
                            for k, xk in enumerate(stations)])
    chord, thickness = chord_and_thickness(blade, x) if not blade.step else \
        (np.tensordot(scales[:, 0], weights, axes=1), np.tensordot(scales[:, 1], weights, axes=1))
    out = {key: np.zeros_like(x) for key in _SCALING}
    for weight, section, (ck, tk) in zip(weights, sections, scales):
        for key, value in _station_values(section, nu).items():
            if value is not None:
                a, b = _SCALING[key]
                out[key] = out[key] + weight * value * (chord / ck) ** a * (thickness / tk) ** b
    if nu is None:
        out["kappa_v"] = out["kappa_w"] = None
    return SpanSections(**out)

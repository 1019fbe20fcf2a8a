"""Parameters of the shrouded blade, its contact and its runs.

One schema serves scene files, ``--set key=value`` and the Python API. Every
value is checked here, once; model builders downstream trust what they get.
Units are SI (m, kg, s, N, Pa) unless the key says otherwise (``*_deg``,
``rpm``). Defaults are the paper's Table 2 and Sect. 2.2
(docs/geometry.md).

Example
-------
>>> p = Parameters.from_mapping({"contact": {"gap": 1e-4}})
>>> round(p.contact.N0, 6)
-1000.0
>>> p.with_overrides(["speed.rpm=8500"]).speed.rpm
8500.0
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import tomllib
from dataclasses import dataclass, field, fields
from typing import Any, Mapping

from shroud.base.errors import InputError


@dataclass(frozen=True)
class Blade:
    disk_radius: float = 0.150   # R_d, m
    length: float = 0.150        # L, m
    width: float = 0.040         # b, chord (along e_w), m
    thickness: float = 0.007     # h, thickness (along e_v), m
    stagger_deg: float = 30.0    # beta_1
    twist_deg: float = 10.0      # beta_t: beta(x) = beta_1 + beta_t x / L
    section: str = "rectangle"   # "rectangle" or "naca4" (geometry.md, "Airfoil blades")
    naca_m: float = 0.04         # NACA camber, share of the chord
    naca_p: float = 0.4          # chord position of the camber's maximum, share of the chord
    chord_taper: float = 1.0     # c(L) / c(0), c(0) = width
    thickness_taper: float = 1.0  # t(L) / t(0), t(0) = thickness
    step: str = ""               # a STEP file of blade and shroud ("" = none)

    @property
    def area(self) -> float:
        return self.width * self.thickness

    def check_modelled(self, profile: bool = False, step: bool = False) -> None:
        """Refuse (InputError) the blade keys the path at hand cannot honour: blade.step unless ``step``
        (the beams and the solid's modes read it), a NACA section or a taper unless ``profile`` (the beam models, the
        solid models and ``shroud section`` take them)."""
        if self.step and not step:
            raise InputError("blade.step", f"{self.step!r}: only the beams (reduced, full, extended: modal, "
                                           "transient, static, sweep, HB) and the solid's modes (shroud modal "
                                           '--model fe) read a STEP file yet; allowed: "" (the blade of the '
                                           "blade.* keys)")
        if profile:
            return
        not_yet = ("only the beam models (reduced, full, extended), the solid models (fe, fe-reduced), the shell "
                   "models (shell, shell-reduced) and the study airfoil take it yet")
        if self.section != "rectangle":
            raise InputError("blade.section", f"{self.section!r}: {not_yet}; allowed: \"rectangle\" "
                                              "(shroud section computes the profile)")
        for key in ("chord_taper", "thickness_taper"):
            if getattr(self, key) != 1.0:
                raise InputError(f"blade.{key}", f"{getattr(self, key)!r}: {not_yet}; allowed: 1 "
                                                 "(shroud section computes the tapered sections)")

    @property
    def I_v(self) -> float:
        """Second moment for bending along e_v (flap, about e_w), m^4."""
        return self.width * self.thickness**3 / 12.0

    @property
    def I_w(self) -> float:
        """Second moment for bending along e_w (chord, about e_v), m^4."""
        return self.thickness * self.width**3 / 12.0

    def beta(self, x):
        """Section angle beta(x) in rad (geometry.md)."""
        return math.radians(self.stagger_deg) + math.radians(self.twist_deg) * x / self.length


@dataclass(frozen=True)
class Material:
    E: float = 200e9      # Pa
    rho: float = 7800.0   # kg/m^3
    nu: float = 0.3

    @property
    def G(self) -> float:
        return self.E / (2.0 * (1.0 + self.nu))


@dataclass(frozen=True)
class Shroud:
    length: float = 0.040     # l_s, along e_ws, m
    width: float = 0.020      # b_s, along e_vs (between the two contact faces), m
    thickness: float = 0.007  # t_s, along X, m; 0 = no shroud


@dataclass(frozen=True)
class Contact:
    enabled: bool = True
    kn: float = 1e7           # N/m, total per side
    kt: float = 1e7           # N/m, total per side
    mu: float = 0.3
    alpha_deg: float = 15.0   # shroud inclination
    N0: float = 0.0           # N per side; < 0 is a gap of -N0/kn
    gap: float | None = None  # m; if given, N0 = -kn * gap (validated: not both)

    @property
    def gap_m(self) -> float:
        """Initial gap Delta = -N0/kn (0 when preloaded or touching), m."""
        return max(0.0, -self.N0 / self.kn)


@dataclass(frozen=True)
class Damping:
    xi1: float = 0.02
    xi2: float = 0.04


@dataclass(frozen=True)
class Load:
    F0: float = 150.0   # N/m, amplitude per unit length along e_v
    ke: int = 2         # excitation order: F0 sin(ke * Omega * t)


@dataclass(frozen=True)
class Speed:
    rpm: float = 10000.0          # the Fig. 8 case
    rpm_per_s: float = 0.0        # angular acceleration; 0 = constant speed (no K_acc)

    @property
    def omega(self) -> float:
        """Rotation speed Omega, rad/s."""
        return 2.0 * math.pi * self.rpm / 60.0


@dataclass(frozen=True)
class Time:
    periods: int = 100
    steps_per_period: int = 256
    contact: str = "implicit"    # "implicit" | "explicit"


@dataclass(frozen=True)
class Reduced:
    N: int = 6       # shape functions per field (5N DOF)
    nr: int = 6      # kept free-interface modes; 0 = full model
    torsion: bool = False   # true: a sixth field, the twist (reduced_model.beam); false: the paper's model
    shroud: str = "point"   # "point": the paper's tip mass; "rigid": a rigid body with offset and rotary inertia


@dataclass(frozen=True)
class FE:
    mesh_size: float = 0.005   # m; chosen by the mesh-convergence scene (scenes/convergence.toml)
    order: int = 2             # polynomial degree of the displacement
    cell: str = "hex"          # "hex" (swept hexahedra: meshes.hexa) or "tet" (free tetrahedra)
    hex_span_ratio: float = 1.0  # hex cells: length along the span / fe.mesh_size
    cms_modes: int = 24        # kept modes of the reduced FE model
    interface_modes: int = 8   # kept contact-face patterns of fe-reduced (0 = all); see bench_fe_transient


@dataclass(frozen=True)
class Shell:
    mesh_size: float = 0.004   # m; element size of the mid-surface mesh (reference_fe.shell, docs/shell.md)
    order: int = 2             # polynomial degree of the displacement (rotations: Crouzeix-Raviart)
    cms_modes: int = 24        # kept modes of the reduced shell model (the paper's 24)
    contact_points: int = 11   # contact points per shroud face (the paper's 11)


@dataclass(frozen=True)
class Ring:
    """N blades on a rigid disk, coupled through their shrouds (geometry.md, "Moving neighbours").

    blades = 0 is the paper's blade between two fixed neighbours. Blade j's
    E (and with it G) is E (1 + d_j): d_j from ``mistuning`` (N values) or,
    when ``mistuning_std`` > 0, drawn from a normal law with that standard
    deviation and ``seed``.
    """

    blades: int = 0                        # N; 0 = the paper's fixed neighbours
    mistuning: tuple[float, ...] = ()      # d_j, j = 0 .. N-1 (empty: tuned, or drawn)
    mistuning_std: float = 0.0             # standard deviation of the drawn d_j
    seed: int = 0                          # of the drawn d_j

    @property
    def deviations(self) -> tuple[float, ...]:
        """d_j of the N blades (all 0 when tuned)."""
        if self.mistuning:
            return self.mistuning
        if self.mistuning_std > 0.0:
            import numpy as np             # only a mistuned ring draws
            rng = np.random.default_rng(self.seed)
            return tuple(float(d) for d in rng.normal(0.0, self.mistuning_std, self.blades))
        return (0.0,) * self.blades

    @property
    def tuned(self) -> bool:
        return not any(self.deviations)


@dataclass(frozen=True)
class Disk:
    """The flexible disk sector under each blade (geometry.md, "The disk"; docs/disk.md).

    thickness = 0 is the rigid disk (the blade's root face clamped). With
    thickness > 0 the solid FE sector of blade and disk, bore clamped, one
    nodal diameter at a time (reference_fe.cyclic). ``E_factor`` scales the
    disk's Young's modulus only (1: the blade's steel; 1000: the rigid-disk
    limit the sector is checked against).
    """

    thickness: float = 0.0       # axial extent of the disk, m (0 = rigid disk; 0.04 is the usual flexible one)
    bore_radius: float = 0.05    # R_i, m: the clamped bore
    E_factor: float = 1.0        # the disk's E / material.E

    def check_rigid(self) -> None:
        """Refuse (InputError) a flexible disk on a path that only has the rigid one."""
        if self.thickness > 0:
            raise InputError("disk.thickness", f"{self.thickness!r}: only `modal --model fe` "
                                               "builds the flexible disk sector; allowed: 0 (the rigid disk) here")


SECTIONS: dict[str, type] = {
    "blade": Blade, "material": Material, "shroud": Shroud, "contact": Contact,
    "damping": Damping, "load": Load, "speed": Speed, "time": Time,
    "reduced": Reduced, "fe": FE, "shell": Shell, "ring": Ring, "disk": Disk,
}


# The beam and the solid are linear, small-strain models of the centrifugally prestressed blade
# (paper Sect. 2; reference_fe: linear prestress). Past this centrifugal strain at the blade root
# they describe nothing (steel yields near 0.2 %); the paper's studies reach 8 % (70000 r/min).
MAX_ROOT_STRAIN = 0.10
# The four-digit thickness law describes profiles up to this thickness over chord (NACA's digits 00..40)
MAX_NACA_THICKNESS = 0.40


def _positive(v): return v > 0
def _nonneg(v): return v >= 0


# key -> (predicate, what is allowed). Keys absent here only need the right type.
_RULES: dict[str, tuple[Any, str]] = {
    "blade.disk_radius": (_nonneg, "a length >= 0 m"),
    "blade.length": (_positive, "a length > 0 m"),
    "blade.width": (_positive, "a length > 0 m"),
    "blade.thickness": (_positive, "a length > 0 m"),
    "blade.stagger_deg": (lambda v: -180 <= v <= 180, "an angle in [-180, 180] deg"),
    "blade.twist_deg": (lambda v: -90 <= v <= 90, "an angle in [-90, 90] deg"),
    "blade.section": (lambda v: v in ("rectangle", "naca4"), '"rectangle" or "naca4"'),
    "blade.naca_m": (lambda v: 0 <= v <= 0.09, "a camber in [0, 0.09] of the chord (NACA's first digit / 100)"),
    "blade.naca_p": (lambda v: 0.1 <= v <= 0.9, "a position in [0.1, 0.9] of the chord (NACA's second digit / 10)"),
    "blade.chord_taper": (lambda v: 0.2 <= v <= 5, "a tip/root chord ratio in [0.2, 5]"),
    "blade.thickness_taper": (lambda v: 0.2 <= v <= 5, "a tip/root thickness ratio in [0.2, 5]"),
    "material.E": (_positive, "a modulus > 0 Pa"),
    "material.rho": (_positive, "a density > 0 kg/m^3"),
    "material.nu": (lambda v: -1.0 < v < 0.5, "a Poisson ratio in (-1, 0.5)"),
    "shroud.length": (_nonneg, "a length >= 0 m"),
    "shroud.width": (_nonneg, "a length >= 0 m"),
    "shroud.thickness": (_nonneg, "a length >= 0 m (0 = no shroud)"),
    "contact.kn": (_positive, "a stiffness > 0 N/m"),
    "contact.kt": (_nonneg, "a stiffness >= 0 N/m"),
    "contact.mu": (_nonneg, "a friction coefficient >= 0"),
    "contact.alpha_deg": (lambda v: -90 < v < 90, "an angle in (-90, 90) deg"),
    "contact.N0": (math.isfinite, "a finite force in N (negative = gap)"),
    "contact.gap": (lambda v: v is None or v >= 0, "a gap >= 0 m"),
    "damping.xi1": (lambda v: 0 <= v < 1, "a damping ratio in [0, 1)"),
    "damping.xi2": (lambda v: 0 <= v < 1, "a damping ratio in [0, 1)"),
    "load.F0": (math.isfinite, "a finite load in N/m"),
    "load.ke": (lambda v: v >= 1, "an integer excitation order >= 1"),
    "speed.rpm": (_nonneg, "a speed >= 0 r/min"),
    "speed.rpm_per_s": (math.isfinite, "a finite angular acceleration in r/min/s"),
    "time.periods": (lambda v: v >= 1, "an integer >= 1"),
    "time.steps_per_period": (lambda v: v >= 16, "an integer >= 16 steps per excitation period"),
    "time.contact": (lambda v: v in ("implicit", "explicit"), '"implicit" or "explicit"'),
    "reduced.N": (lambda v: 1 <= v <= 40, "an integer in [1, 40]"),
    "reduced.nr": (lambda v: v >= 0, "an integer >= 0 (0 = full model)"),
    "reduced.shroud": (lambda v: v in ("point", "rigid"), '"point" (the paper\'s tip mass) or "rigid" (a rigid body)'),
    "fe.mesh_size": (_positive, "an element size > 0 m"),
    "fe.order": (lambda v: v in (1, 2), "1 or 2"),
    "fe.cell": (lambda v: v in ("tet", "hex"), '"tet" or "hex"'),
    "fe.hex_span_ratio": (lambda v: 0.25 <= v <= 8, "a ratio in [0.25, 8]"),
    "fe.cms_modes": (lambda v: v >= 1, "an integer >= 1"),
    "fe.interface_modes": (lambda v: v >= 0, "an integer >= 0 (0 keeps every contact attachment mode)"),
    "shell.mesh_size": (_positive, "an element size > 0 m"),
    "shell.order": (lambda v: v == 2, "2 (P2 displacements with Crouzeix-Raviart rotations)"),
    "shell.cms_modes": (lambda v: v >= 1, "an integer >= 1"),
    "shell.contact_points": (lambda v: v >= 2, "an integer >= 2 points per shroud face"),
    "ring.blades": (lambda v: v == 0 or v >= 2, "0 (the paper's fixed neighbours) or an integer >= 2 blades"),
    "ring.mistuning": (lambda v: all(d > -1.0 for d in v), "relative changes d_j > -1 of E (E (1 + d_j) > 0)"),
    "ring.mistuning_std": (_nonneg, "a standard deviation >= 0"),
    "disk.thickness": (_nonneg, "a length >= 0 m (0 = the rigid disk)"),
    "disk.bore_radius": (_positive, "a radius > 0 m"),
    "disk.E_factor": (_positive, "a factor > 0 on the disk's E"),
}
# The blade's root is extended this far inside the rim (geometry.md, "The disk"), m
DISK_ROOT_DEPTH = 0.002


def all_keys() -> list[str]:
    return [f"{s}.{f.name}" for s, cls in SECTIONS.items() for f in fields(cls)]


def _type_of(section: str, name: str) -> type:
    hint = {f.name: f for f in fields(SECTIONS[section])}[name].type
    return {"float": float, "int": int, "bool": bool, "str": str,
            "float | None": float, "tuple[float, ...]": tuple}[hint]


def _coerce(key: str, value: Any, typ: type) -> Any:
    """Convert a scene or --set value to the key's type, or raise InputError."""
    if value is None and key == "contact.gap":
        return None
    if typ is tuple:
        return _coerce_list(key, value)
    if isinstance(value, str) and typ is not str:
        text = value.strip()
        if typ is bool:
            if text.lower() in ("true", "1", "yes", "on"):
                return True
            if text.lower() in ("false", "0", "no", "off"):
                return False
            raise InputError(key, f"{value!r} is not a boolean; allowed: true or false")
        try:
            value = float(text) if typ is float else int(text)
        except ValueError:
            raise InputError(key, f"{value!r} is not a number; allowed: {_allowed(key, typ)}") from None
    if typ is bool:
        if not isinstance(value, bool):
            raise InputError(key, f"{value!r} is not a boolean; allowed: true or false")
        return value
    if typ is str:
        if not isinstance(value, str):
            raise InputError(key, f"{value!r} is not a string; allowed: {_allowed(key, typ)}")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(key, f"{value!r} is not a number; allowed: {_allowed(key, typ)}")
    if typ is int:
        if float(value) != int(value):
            raise InputError(key, f"{value!r} is not an integer; allowed: {_allowed(key, typ)}")
        return int(value)
    value = float(value)
    if not math.isfinite(value):
        raise InputError(key, f"{value!r} is not finite; allowed: {_allowed(key, typ)}")
    return value


def _coerce_list(key: str, value: Any) -> tuple[float, ...]:
    """A list of numbers: a TOML array, or ``--set`` text such as ``0.01,-0.02`` or ``[0.01, -0.02]``."""
    if isinstance(value, str):
        text = value.strip().removeprefix("[").removesuffix("]")
        value = [t for t in text.split(",") if t.strip()]
    if not isinstance(value, (list, tuple)):
        raise InputError(key, f"{value!r} is not a list; allowed: a list of numbers, e.g. [0.01, -0.02]")
    return tuple(_coerce(key, v, float) for v in value)


def _allowed(key: str, typ: type) -> str:
    rule = _RULES.get(key)
    return rule[1] if rule else typ.__name__


def parse_value(text: str) -> Any:
    """A ``--set`` value: a TOML value (``8500``, ``1e-4``, ``"explicit"``, ``[4, 6]``, ``true``), else the bare word.

    >>> parse_value('"explicit"'), parse_value("explicit"), parse_value("1e-4"), parse_value("[4, 6]")
    ('explicit', 'explicit', 0.0001, [4, 6])
    """
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text          # bare words are strings


def unknown_key(key: str, known: list[str]) -> InputError:
    near = difflib.get_close_matches(key, known, n=1)
    hint = f" (did you mean {near[0]}?)" if near else ""
    return InputError(key, f"unknown key{hint}; allowed keys: " + ", ".join(known))


@dataclass(frozen=True)
class Parameters:
    """The whole, validated parameter set (geometry.md defaults)."""

    blade: Blade = field(default_factory=Blade)
    material: Material = field(default_factory=Material)
    shroud: Shroud = field(default_factory=Shroud)
    contact: Contact = field(default_factory=Contact)
    damping: Damping = field(default_factory=Damping)
    load: Load = field(default_factory=Load)
    speed: Speed = field(default_factory=Speed)
    time: Time = field(default_factory=Time)
    reduced: Reduced = field(default_factory=Reduced)
    fe: FE = field(default_factory=FE)
    shell: Shell = field(default_factory=Shell)
    ring: Ring = field(default_factory=Ring)
    disk: Disk = field(default_factory=Disk)

    # --- construction -----------------------------------------------------
    @classmethod
    def from_mapping(cls, tables: Mapping[str, Any], base: "Parameters | None" = None) -> "Parameters":
        """Build from nested tables ``{"blade": {"length": 0.15}, ...}`` over ``base``."""
        flat: dict[str, Any] = {}
        for section, table in tables.items():
            if section not in SECTIONS:
                raise unknown_key(section, all_keys())
            if not isinstance(table, Mapping):
                raise InputError(section, "must be a table of keys, e.g. [%s]" % section)
            for name, value in table.items():
                flat[f"{section}.{name}"] = value
        return (base or cls()).updated(flat)

    def with_overrides(self, assignments: list[str]) -> "Parameters":
        """Apply ``--set key=value`` strings (values read as TOML, bare words as strings).

        >>> Parameters().with_overrides(['time.contact="explicit"', "reduced.shroud=rigid"]).time.contact
        'explicit'
        """
        flat = {}
        for text in assignments:
            key, sep, value = text.partition("=")
            if not sep:
                raise InputError(text, "--set needs key=value, e.g. --set speed.rpm=8500")
            flat[key.strip()] = parse_value(value.strip())
        return self.updated(flat)

    def updated(self, flat: Mapping[str, Any]) -> "Parameters":
        """A copy with ``{"section.name": value}`` replaced, validated."""
        known = all_keys()
        sections = {s: dataclasses.asdict(getattr(self, s)) for s in SECTIONS}
        touched: set[str] = set()
        for key, value in flat.items():
            section, _, name = key.partition(".")
            if key not in known:
                raise unknown_key(key, known)
            sections[section][name] = _coerce(key, value, _type_of(section, name))
            touched.add(key)
        contact = sections["contact"]
        if "contact.gap" in touched and "contact.N0" in touched and contact["gap"] is not None:
            raise InputError("contact.gap", "give contact.N0 or contact.gap, not both")
        if "contact.N0" in touched:
            contact["gap"] = None          # a new preload replaces an inherited gap
        for key in known:
            section, _, name = key.partition(".")
            rule = _RULES.get(key)
            value = sections[section][name]
            if rule and value is not None and not rule[0](value):
                raise InputError(key, f"{value!r} is out of range; allowed: {rule[1]}")
        if contact["gap"] is not None:
            contact["N0"] = -contact["kn"] * contact["gap"]
        new = Parameters(**{s: SECTIONS[s](**sections[s]) for s in SECTIONS})
        new._check_geometry()
        new._check_speed()
        new._check_ring()
        new._check_disk()
        return new

    def _check_geometry(self) -> None:
        b, s = self.blade, self.shroud
        tip = b.thickness * b.thickness_taper / (b.width * b.chord_taper)
        if b.section == "naca4" and max(b.thickness / b.width, tip) > MAX_NACA_THICKNESS:
            raise InputError("blade.thickness", f"{b.thickness!r} with blade.width {b.width!r} and the tapers makes a "
                             f"profile {100 * max(b.thickness / b.width, tip):.3g} % of its chord thick; allowed: "
                             f"at most {100 * MAX_NACA_THICKNESS:g} % at root and tip (NACA's last two digits)")
        if s.thickness > 0 and s.width < b.thickness:
            raise InputError("shroud.width",
                             f"{s.width!r} is narrower than blade.thickness {b.thickness!r}; "
                             "allowed: a shroud at least as wide as the blade is thick")
        if s.thickness > 0 and s.length <= 0:
            raise InputError("shroud.length", "must be > 0 m when shroud.thickness > 0")

    def root_strain(self, rpm: float) -> float:
        """Centrifugal strain at the blade root at ``rpm``: (rho Omega^2 (R L + L^2/2) + m_s Omega^2 (R + L) / A) / E.

        >>> round(100 * Parameters().root_strain(30000), 2)      # the paper's highest speed, per cent
        1.53
        """
        b, omega = self.blade, 2.0 * math.pi * rpm / 60.0
        stress = (self.material.rho * (b.disk_radius * b.length + 0.5 * b.length**2)
                  + self.shroud_mass * (b.disk_radius + b.length) / b.area) * omega**2
        return stress / self.material.E

    @property
    def max_rpm(self) -> float:
        """The speed at which the root strain reaches MAX_ROOT_STRAIN, r/min (strain grows as rpm^2)."""
        return 1000.0 * math.sqrt(MAX_ROOT_STRAIN / self.root_strain(1000.0))

    def _check_speed(self) -> None:
        rpm = max(self.speed.rpm, 0.0)
        if rpm > self.max_rpm:
            raise InputError("speed.rpm", f"{rpm:g} r/min strains the blade root by {100 * self.root_strain(rpm):.3g} % "
                             "under its own centrifugal load; the beam and the solid are linear, small-strain "
                             f"models, meaningless past {100 * MAX_ROOT_STRAIN:g} % (steel yields near 0.2 %); "
                             f"allowed: a speed <= {self.max_rpm:.0f} r/min for this blade")
    def _check_ring(self) -> None:
        r = self.ring
        if r.blades == 0:
            if r.mistuning or r.mistuning_std > 0:
                raise InputError("ring.mistuning", "mistunes the blades of a ring; allowed: with ring.blades >= 2")
            return
        if r.mistuning and r.mistuning_std > 0:
            raise InputError("ring.mistuning", "give ring.mistuning or ring.mistuning_std, not both")
        if r.mistuning and len(r.mistuning) != r.blades:
            raise InputError("ring.mistuning", f"has {len(r.mistuning)} values for {r.blades} blades; "
                                               "allowed: one d_j per blade (ring.blades values)")
        worst = min(r.deviations)
        if worst <= -1.0:
            raise InputError("ring.mistuning_std", f"{r.mistuning_std!r} with seed {r.seed} draws d = {worst:.3g}, "
                                                   "a blade with E <= 0; allowed: a scatter whose draws keep d_j > -1")

    def _check_disk(self) -> None:
        """A flexible disk needs a ring to be a sector of, a bore inside the rim and a rim that holds the
        blade's root section (extended DISK_ROOT_DEPTH inside the rim) axially and within the sector."""
        d, b = self.disk, self.blade
        if d.thickness == 0:
            return
        if self.ring.blades < 2:
            raise InputError("disk.thickness", f"{d.thickness!r} makes a disk sector, which needs the ring it is a "
                                               "sector of; allowed: with ring.blades >= 2")
        if d.bore_radius >= b.disk_radius - DISK_ROOT_DEPTH:
            raise InputError("disk.bore_radius", f"{d.bore_radius!r} is not inside the rim (blade.disk_radius "
                                                 f"{b.disk_radius!r} less the root's {DISK_ROOT_DEPTH} m); allowed: "
                                                 f"a bore radius < {b.disk_radius - DISK_ROOT_DEPTH:g} m")
        beta = math.radians(b.stagger_deg)
        half_y = 0.5 * (b.width * abs(math.sin(beta)) + b.thickness * abs(math.cos(beta)))
        half_z = 0.5 * (b.width * abs(math.cos(beta)) + b.thickness * abs(math.sin(beta)))
        root_x = b.disk_radius - DISK_ROOT_DEPTH
        if half_z > 0.5 * d.thickness:
            raise InputError("disk.thickness", f"{d.thickness!r} is thinner than the blade's root section, "
                                               f"{2 * half_z:.4g} m along Z; allowed: >= {2 * half_z:.4g} m")
        most = math.ceil(math.pi / math.atan2(half_y, root_x)) - 1
        if self.ring.blades > most:
            raise InputError("ring.blades", f"{self.ring.blades} sectors are narrower than the blade's root "
                                            f"section ({2 * half_y:.4g} m along Y at {root_x:g} m); allowed: "
                                            f"ring.blades <= {most} with disk.thickness > 0")

    # --- views -------------------------------------------------------------
    def flat(self) -> dict[str, Any]:
        return {f"{s}.{k}": v for s in SECTIONS for k, v in dataclasses.asdict(getattr(self, s)).items()}

    def as_tables(self) -> dict[str, dict[str, Any]]:
        return {s: dataclasses.asdict(getattr(self, s)) for s in SECTIONS}

    @property
    def shroud_mass(self) -> float:
        """m_s = rho l_s b_s t_s, the tip mass of the beam model, kg."""
        s = self.shroud
        return self.material.rho * s.length * s.width * s.thickness

    @property
    def time_step(self) -> float:
        """dt = 60 / (steps_per_period * ke * rpm), s (256 per period as the paper).

        Every time integration takes its step from here, so this is the one
        place that refuses a speed of 0 for one: at rest there is no
        excitation period to step through (modal analyses at rest are fine).

        >>> Parameters().time_step                      # 10000 r/min, ke = 2, 256 steps per period
        1.171875e-05
        >>> Parameters().updated({"speed.rpm": 0}).time_step
        Traceback (most recent call last):
        ...
        shroud.base.errors.InputError: speed.rpm: 0.0 r/min has no excitation period to step through; allowed: a speed > 0 r/min for a time integration (0 only for modal analyses)
        """
        if not self.speed.rpm > 0:
            raise InputError("speed.rpm", f"{self.speed.rpm!r} r/min has no excitation period to step through; "
                             "allowed: a speed > 0 r/min for a time integration (0 only for modal analyses)")
        return 60.0 / (self.time.steps_per_period * self.load.ke * self.speed.rpm)

"""The parameter layer: defaults are the paper's Table 2, derived values follow
their definitions, and every bad value is refused with its key named."""

import math

import pytest

from shroud.base.errors import InputError
from shroud.params import Parameters, all_keys


def test_defaults_are_table_2():
    p = Parameters()
    b, m, s = p.blade, p.material, p.shroud
    assert (m.E, m.rho, m.nu) == (200e9, 7800.0, 0.3)
    assert (b.disk_radius, b.length, b.width, b.thickness) == (0.150, 0.150, 0.040, 0.007)
    assert (b.stagger_deg, b.twist_deg) == (30.0, 10.0)
    assert (s.length, s.width, s.thickness) == (0.040, 0.020, 0.007)
    assert (p.contact.kn, p.contact.kt, p.contact.mu, p.contact.alpha_deg) == (1e7, 1e7, 0.3, 15.0)
    assert (p.damping.xi1, p.damping.xi2, p.load.F0, p.load.ke) == (0.02, 0.04, 150.0, 2)


def test_derived_values():
    p = Parameters().with_overrides(["speed.rpm=10000"])
    assert p.shroud_mass == pytest.approx(7800 * 0.040 * 0.020 * 0.007)
    # 256 steps per excitation period of ke * rpm / 60 Hz
    assert p.time_step * 256 == pytest.approx(1.0 / (2 * 10000 / 60))
    assert p.speed.omega == pytest.approx(2 * math.pi * 10000 / 60)
    assert p.blade.beta(p.blade.length) == pytest.approx(math.radians(40.0))


def test_gap_sets_negative_preload_and_back():
    p = Parameters().with_overrides(["contact.gap=6e-4"])
    assert p.contact.N0 == pytest.approx(-1e7 * 6e-4)
    assert p.contact.gap_m == pytest.approx(6e-4)
    # a later preload replaces the inherited gap
    q = p.with_overrides(["contact.N0=10"])
    assert q.contact.N0 == 10.0 and q.contact.gap is None and q.contact.gap_m == 0.0
    # stiffer contact at the same gap keeps the gap, not the force
    r = Parameters.from_mapping({"contact": {"gap": 1e-4, "kn": 2e7}})
    assert r.contact.N0 == pytest.approx(-2e3)


@pytest.mark.parametrize("assignment, key", [
    ("blade.thickness=-0.001", "blade.thickness"),
    ("material.nu=0.5", "material.nu"),
    ("reduced.N=0", "reduced.N"),
    ("contact.mu=-0.1", "contact.mu"),
    ("contact.kn=-1", "contact.kn"),
    ("time.steps_per_period=15", "time.steps_per_period"),
    ("time.contact=semi", "time.contact"),
    ("reduced.N=2.5", "reduced.N"),
    ("speed.rpm=fast", "speed.rpm"),
    ("contact.enabled=maybe", "contact.enabled"),
    ("blade.lenght=0.1", "blade.lenght"),
    ("shroud.width=0.005", "shroud.width"),       # narrower than the blade is thick
    ("material.E=nan", "material.E"),
    ("blade.section=naca6", "blade.section"),
    ("blade.naca_m=0.1", "blade.naca_m"),
    ("blade.naca_p=0.05", "blade.naca_p"),
    ("blade.chord_taper=0", "blade.chord_taper"),
    ("blade.thickness_taper=6", "blade.thickness_taper"),
    ("blade.step=3", "blade.step"),                # a file name, not a number
])
def test_bad_values_name_their_key(assignment, key):
    with pytest.raises(InputError) as err:
        Parameters().with_overrides([assignment])
    assert err.value.key == key
    assert err.value.line().startswith(f"error: {key}: ")
    assert "\n" not in err.value.line()


@pytest.mark.parametrize("assignment, share", [("blade.thickness=0.017", "42.5"), ("blade.chord_taper=0.2", "87.5")])
def test_a_naca_profile_thicker_than_the_four_digit_law_is_refused(assignment, share):
    """The law describes profiles up to 40 % of their chord: 17 mm on 40 mm at the root, or the default
    7 mm root on a tip chord of 0.2 x 40 mm, are refused; the rectangle has no such bound."""
    with pytest.raises(InputError, match=f"blade.thickness: .* {share} % of its chord"):
        Parameters().with_overrides(["blade.section=naca4", assignment])
    assert Parameters().with_overrides([assignment]).blade.section == "rectangle"


def test_the_airfoil_keys_default_to_the_papers_rectangle():
    b = Parameters().blade
    assert (b.section, b.naca_m, b.naca_p, b.chord_taper, b.thickness_taper, b.step) == ("rectangle", 0.04, 0.4,
                                                                                       1.0, 1.0, "")


def test_gap_and_preload_together_refused():
    with pytest.raises(InputError, match="not both"):
        Parameters.from_mapping({"contact": {"gap": 1e-4, "N0": 5.0}})


def test_every_key_round_trips_through_set():
    p = Parameters()
    flat = p.flat()
    assert sorted(flat) == sorted(all_keys())
    again = p.updated({k: v for k, v in flat.items() if v is not None and k != "contact.N0"})
    assert again == p

"""Unit factors and unit parsing against published definitions, not against pydrill's table.

Found by a mutation audit of pydrill/units.py: a wrong psi, Mpsi, g/cm3, m/h, ft/h or km
factor, a dropped spelling, or a refusal removed, passed every other test. The expected values
here are computed from the exact definitions (NIST SP 811, Appendix B):
1 ft = 0.3048 m, 1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, g_n = 9.80665 m/s², 1 h = 3600 s.
"""

import math

import numpy as np
import pytest

from pydrill import units

FT = 0.3048
INCH = 0.0254
LBF = 4.4482216152605
G_N = 9.80665

# (text, kind, SI value) from the definitions above; psi = lbf/in² = 6894.757293168361 Pa
PUBLISHED = [
    ("1 m", "length", 1.0),
    ("250 mm", "length", 0.25),
    ("250 cm", "length", 2.5),
    ("3 km", "length", 3000.0),
    ("5 in", "length", 5 * INCH),
    ("3000 ft", "length", 914.4),
    ("100 kN", "force", 1e5),
    ("25 klbf", "force", 25_000 * LBF),
    ("25 kips", "force", 25_000 * LBF),
    ("25 kip", "force", 25_000 * LBF),
    ("10 tonne", "force", 10_000 * G_N),
    ("10 tonnes", "force", 10_000 * G_N),
    ("10 t", "force", 10_000 * G_N),
    ("12 kN·m", "torque", 12_000.0),
    ("6600 ft·lbf", "torque", 6600 * FT * LBF),
    ("6.6 kft·lbf", "torque", 6600 * FT * LBF),
    ("6600 lbs-ft", "torque", 6600 * FT * LBF),
    ("6600 lbsft", "torque", 6600 * FT * LBF),
    ("6.6 klbs-ft", "torque", 6600 * FT * LBF),
    ("6600 ft.lbf", "torque", 6600 * FT * LBF),
    ("12 kN.m", "torque", 12_000.0),
    ("120 rpm", "velocity", 120 * 2 * math.pi / 60),
    ("79.3 GPa", "modulus", 79.3e9),
    ("200 MPa", "modulus", 2e8),
    ("1 psi", "modulus", 6894.757293168361),
    ("30000 psi", "modulus", 30_000 * LBF / INCH**2),
    ("11.5 Mpsi", "modulus", 11.5e6 * LBF / INCH**2),
    ("7.85 g/cm3", "density", 7850.0),
    ("7850 kg/m^3", "density", 7850.0),
    ("36 m/h", "rate", 0.01),
    ("36 m/hr", "rate", 0.01),
    ("100 ft/h", "rate", 100 * FT / 3600),
    ("100 ft/hr", "rate", 100 * FT / 3600),
]


@pytest.mark.parametrize(("text", "kind", "si"), PUBLISHED)
def test_parse_matches_the_published_definition(text, kind, si):
    assert units.parse(text, kind) == pytest.approx(si, rel=1e-12)


def test_psi_is_a_pound_force_per_square_inch():
    # NIST SP 811: 1 psi = 6.894757 E+03 Pa; 11.5 Mpsi is steel's shear modulus, ~79.3 GPa
    assert units.parse("1 psi", "modulus") == pytest.approx(6.894757e3, rel=1e-7)
    assert units.parse("11.5 Mpsi", "modulus") == pytest.approx(79.29e9, rel=1e-3)


@pytest.mark.parametrize(("text", "kind", "si"), PUBLISHED)
def test_convert_inverts_parse(text, kind, si):
    """convert(SI, kind, unit) gives back the number written with that unit."""
    number, unit = text.split(" ", 1)
    assert units.convert(si, kind, unit) == pytest.approx(float(number), rel=1e-12)


def test_convert_of_arrays_divides_by_the_factor():
    si = np.array([0.0, 914.4, 1828.8])
    assert np.allclose(units.convert(si, "length", "ft"), [0.0, 3000.0, 6000.0], rtol=1e-14)
    assert units.convert(2 * math.pi, "velocity", "rpm") == pytest.approx(60.0, rel=1e-14)


def test_negative_values_keep_their_sign():
    # a torque turning the string backwards, written with a unit
    assert units.parse("-5 kN·m", "torque") == -5000.0
    assert units.parse("-1 ft·lbf", "torque") == pytest.approx(-FT * LBF, rel=1e-14)


def test_bools_are_refused_not_read_as_one_or_zero():
    for value in (True, False):
        with pytest.raises(ValueError, match="is not a"):
            units.parse(value, "force")


def test_a_value_overflowing_with_its_factor_is_refused():
    # 1e306 klbf is 4.4e309 N: beyond a float, inf must not come back
    with pytest.raises(ValueError, match="beyond the range of a float"):
        units.parse("1e306 klbf", "force")
    with pytest.raises(ValueError, match="beyond the range of a float"):
        units.parse("1e308 km", "length")


@pytest.mark.parametrize("ambiguous", ["10 ton", "10 tons", "10 tonf"])
def test_tons_are_refused(ambiguous):
    with pytest.raises(ValueError, match="ambiguous"):
        units.parse(ambiguous, "force")


@pytest.mark.parametrize(
    ("text", "kind", "meant"),
    [("1 mPa", "modulus", "MPa"), ("1 mpsi", "modulus", "Mpsi"), ("1 Mm", "length", "mm"),
     ("1 MM", "length", "mm")],
)  # fmt: skip
def test_the_case_of_a_milli_or_mega_prefix_is_not_folded(text, kind, meant):
    """Another case names one unit only, and is read as it ("RPM", "MPA", "KN-M"), but for the
    prefixes m (1e-3) and M (1e6): "1 mPa" was read as 1 MPa, 10^9 times what it says."""
    with pytest.raises(ValueError, match=rf"m is milli, M mega; did you mean '{meant}'\?"):
        units.parse(text, kind)


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [("2 MPA", "modulus", 2e6), ("2 MPSI", "modulus", 2e6 * LBF / 0.0254**2),
     ("2 GPA", "modulus", 2e9), ("2 KN-M", "torque", 2e3), ("2 KM", "length", 2e3),
     ("2 Kg/M3", "density", 2.0), ("2 KG·M2", "inertia", 2.0), ("2 M/H", "rate", 2 / 3600),
     ("2 M", "length", 2.0), ("2 RPM", "velocity", 4 * math.pi / 60)],
)  # fmt: skip
def test_other_cases_are_still_read_where_no_prefix_changes(text, kind, si):
    assert units.parse(text, kind) == pytest.approx(si, rel=1e-14)

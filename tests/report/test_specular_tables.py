"""Amanatides' tables against exact rational arithmetic and numerical integration."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from aaeval.specular import tables
from aaeval.specular.tables import max_n_allowed, maximum, min_dot, power_cutoff, power_spectrum


def exact_cutoff(n: int, power: Fraction) -> int:
    """Smallest f with sum_{|n-2k|<=f} C(n,k)^2 >= power * sum_k C(n,k)^2, in integers."""
    weights = [math.comb(n, k) ** 2 for k in range(n + 1)]
    total = sum(weights)
    for f in range(n + 1):
        if Fraction(sum(w for k, w in enumerate(weights) if abs(n - 2 * k) <= f)) >= power * total:
            return f
    raise AssertionError("unreachable")


@pytest.mark.parametrize(
    "n, power, expected",
    [(500, 0.999, 52), (500, 0.99, 40), (160, 0.999, 30)],  # Amanatides 1992 and field notes
)
def test_power_cutoff_published_values(n, power, expected):
    assert power_cutoff(n, power) == expected


@pytest.mark.parametrize("n", [1, 2, 3, 7, 10, 33, 64, 101, 250])
@pytest.mark.parametrize("power", ["0.9", "0.99", "0.999"])
def test_power_cutoff_matches_exact_binomials(n, power):
    assert power_cutoff(n, float(power)) == exact_cutoff(n, Fraction(power))


def test_power_cutoff_one_is_the_highest_frequency():
    assert [power_cutoff(n, 1.0) for n in (0, 1, 5, 500)] == [0, 1, 5, 500]


def test_power_spectrum_matches_numerical_fourier_coefficients():
    # a_m = (1/pi) int cos^n x cos(m x) dx; power of a cosine of amplitude a is a^2/2
    n = 12
    x = np.linspace(-np.pi, np.pi, 20001)
    f = np.cos(x) ** n
    numeric = []
    for m in range(n + 1):
        a = np.trapezoid(f * np.cos(m * x), x) / np.pi
        numeric.append(a * a / 4 if m == 0 else a * a / 2)
    np.testing.assert_allclose(power_spectrum(n), numeric, atol=1e-12)


@pytest.mark.parametrize("n", [0, 2, 10, 160, 500, 1000])
def test_maximum_is_the_dc_component_for_even_n(n):
    assert maximum(n) == pytest.approx(float(Fraction(math.comb(n, n // 2), 2**n)), rel=1e-12)


def test_maximum_500_published():
    assert round(float(maximum(500)), 6) == 0.035665


@pytest.mark.parametrize("n", [1, 3, 7.5, 41])
def test_maximum_is_mean_abs_cos_power_for_any_n(n):
    x = np.linspace(-np.pi / 2, np.pi / 2, 200001)
    assert maximum(n) == pytest.approx(np.trapezoid(np.cos(x) ** n, x) / np.pi, rel=1e-8)


def test_min_dot_conservative_and_aggressive():
    assert min_dot(500) == pytest.approx(math.cos(math.pi / 1000))
    assert min_dot(500, 0.999) == pytest.approx(math.cos(math.pi / (2 * 52)))
    np.testing.assert_allclose(min_dot(np.array([10.0, 20.0])), np.cos(np.pi / np.array([20.0, 40.0])))


@pytest.mark.parametrize("power", [0.99, 0.999])
@pytest.mark.parametrize("frequency", [0.5, 3.0, 7.9, 12.0, 20.0])
def test_max_n_allowed_is_the_largest_fitting_exponent(power, frequency):
    n_max = 120
    n = int(max_n_allowed(frequency, power, n_max))
    exact = [exact_cutoff(m, Fraction(str(power))) for m in range(n_max + 1)]
    assert all(c <= frequency for c in exact[: n + 1])
    assert n == n_max or exact[n + 1] > frequency


def test_max_n_allowed_conservative_is_the_frequency():
    np.testing.assert_array_equal(max_n_allowed(np.array([0.3, 17.2, 900.0]), 1.0, 500), [0.3, 17.2, 500.0])


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.5, float("nan")])
def test_bad_power_is_refused(bad):
    with pytest.raises(ValueError, match="power"):
        power_cutoff(10, bad)


def test_bad_exponent_is_refused():
    with pytest.raises(ValueError, match="exponent"):
        power_cutoff(-1, 0.99)
    with pytest.raises(ValueError, match="exponent"):
        tables.cutoff_table(2.5, 0.99)


def test_clamp_follows_the_papers_code_fragment():
    from aaeval.specular.shading import clamp_amanatides

    n, ks = np.array([500.0, 500.0, 500.0]), np.full(3, 0.8)
    turn = np.array([0.001, 0.01, 0.05])  # radians between the most divergent corner normals
    dot = np.cos(turn)
    n_c, ks_c, flagged = clamp_amanatides(dot, n, ks)
    assert flagged.tolist() == [False, True, True]  # MinDot[500] = cos(pi / 1000)
    frequency = np.pi / (2 * turn[1:])  # sampleFrequency = pi / delta_alpha, delta_alpha = 2 acos(dot)
    np.testing.assert_allclose(n_c, [500.0, *frequency])
    expected_ks = [0.8] + [0.8 * math.comb(500, 250) / 2**500 / float(maximum(f)) for f in frequency]
    np.testing.assert_allclose(ks_c, expected_ks)

    n_a, ks_a, flagged_a = clamp_amanatides(dot, n, ks, power=0.999)
    assert flagged_a.tolist() == [False, False, True]  # aggressive MinDot = cos(pi / (2 * 52))
    exact = [exact_cutoff(m, Fraction("0.999")) for m in range(300)]
    allowed = max(m for m in range(300) if all(c <= frequency[1] for c in exact[: m + 1]))
    assert 160 < allowed < 299  # cutoff(160) = 30 fits under 31.4
    assert n_a[2] == allowed
    assert ks_a[2] == pytest.approx(0.8 * float(maximum(500)) / float(maximum(allowed)))

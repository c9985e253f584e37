"""The stated error of the "cycle" with "envelope" maximum covers its true error (issue 34 A; spec zstk.md §8).

The true maxima come from an independent reference written here: the chain-level sigma_max (every roller, the chain
phase phi_0 over one pitch and the load direction gamma over a turn, ``zstk.sigma_max_at``) on a dense grid, its
largest local maxima refined by nested bounded Brent searches (scipy.optimize.minimize_scalar, x to 1e-13 rad).  It
shares no code with the joint search (one roller's stress over its position and the relative direction, grids,
the bracketed maximisation of gearcalc.roots).  The designs: the fuzz record of issue 34, the shipped
configs/zstk_merko_A_envelope.toml and a seeded set of random chains.
"""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from gearcalc import api
from gearcalc import zstk as z
from gearcalc.zstk import envelope

CONFIGS = Path(__file__).resolve().parent.parent / "configs"

FUZZ = """kind = "zstk"
[geometry]
outer_raceway_radius_mm = 7.034255315488871
inner_raceway_radius_mm = 2.744229891852557
eccentricity_mm = 0.24745724117236048
roller_gap_mm = 1e-09
roller_length_mm = 2.9763014968836328
correct = "outer"
scheme = "cycle"
[load]
radial_N = 563502.5585652901
direction_deg = "envelope"
clearance_mm = 0.0
"""


def fuzz_chain():
    """The fuzz design's chain (N = 6, the largest N <= N* = 6.93; R_H corrected) and its materials (steel)."""
    g = tomllib.loads(FUZZ)["geometry"]
    ch = z.close_chain(g["outer_raceway_radius_mm"], g["inner_raceway_radius_mm"], g["eccentricity_mm"],
                       g["roller_gap_mm"], 6, "outer")
    return ch, z.Materials.from_elastic(g["roller_length_mm"], 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)


def reference_max(ch, mats, load, clearance, phase=None, phases=16, directions=180, top=2):
    """max over the chain phase (one pitch, or the fixed ``phase``) and the load direction of sigma_max: at each of
    ``phases`` phases, the maximum over the directions (a grid of ``directions``, bounded Brent on its two best
    points); then bounded Brent over the phase on the ``top`` largest local maxima of those."""
    from scipy.optimize import minimize_scalar

    opts = {"xatol": 1e-13}
    pitch = 2 * np.pi / ch.n
    gg = 2 * np.pi * np.arange(directions) / directions
    hg = gg[1]

    def over_directions(p):
        row = z.sigma_max_at(ch, mats, p, gg, load, clearance)
        best = float(np.max(row))
        for k in np.argsort(-row)[:2]:
            r = minimize_scalar(lambda x: -float(z.sigma_max_at(ch, mats, p, x, load, clearance)),
                                bounds=(gg[k] - hg, gg[k] + hg), method="bounded", options=opts)
            best = max(best, -r.fun)
        return best

    if phase is not None:
        return over_directions(phase)
    ph = pitch * np.arange(phases) / phases
    values = np.array([over_directions(p) for p in ph])
    ext = np.concatenate([values[-1:], values, values[:1]])  # periodic over the pitch
    peaks = np.flatnonzero((values >= ext[:-2]) & (values >= ext[2:]))
    best = float(np.max(values))
    for j in peaks[np.argsort(-values[peaks])][:top]:
        r = minimize_scalar(lambda p: -over_directions(p), bounds=(ph[j] - ph[1], ph[j] + ph[1]), method="bounded",
                            options=opts)
        best = max(best, -r.fun)
    return best


@pytest.mark.slow
def test_fuzz_record_error_covers_the_true_error(tmp_path):
    # issue 34: stated 0.0085 MPa, true error 0.258 MPa (the refinement stopped 0.5 rad of roller position away
    # from the maximum); the end-to-end result's sigma_max_err_MPa must cover the distance to the reference
    path = tmp_path / "fuzz.toml"
    path.write_text(FUZZ)
    s = api.compute(api.load(path)).summary
    assert s["N"] == 6
    ch, mats = fuzz_chain()
    ref = reference_max(ch, mats, 563502.5585652901, 0.0)
    assert abs(ref - s["sigma_max_MPa"]) <= s["sigma_max_err_MPa"] + 1e-12 * ref
    assert s["sigma_max_err_MPa"] <= 1e-6 * s["sigma_max_MPa"]


CONCENTRIC = FUZZ.replace("7.034255315488871", "20.0").replace("2.744229891852557", "10.0") \
    .replace("0.24745724117236048", "0.0").replace("1e-09", "0.0").replace("2.9763014968836328", "1.0") \
    .replace("563502.5585652901", "1.0")


def test_concentric_design_error_is_finite_and_covers_the_true_error(tmp_path):
    # the design hypothesis found (tests/test_props_zstk.py): e = 0, every roller equal, so sigma_max does not
    # depend on the roller position (flat up to round-off); the joint search's bound came out inf (exit 2).
    # Reference: at e = 0 every chain phase is equivalent (rotational symmetry), so the maximum over the load
    # direction at phase 0 is the answer
    path = tmp_path / "concentric.toml"
    path.write_text(CONCENTRIC)
    s = api.compute(api.load(path)).summary
    assert math.isfinite(s["sigma_max_err_MPa"])
    ch = z.close_chain(20.0, 10.0, 0.0, 0.0, s["N"], "outer")
    mats = z.Materials.from_elastic(1.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    ref = reference_max(ch, mats, 1.0, 0.0, phase=0.0, directions=720)
    assert abs(ref - s["sigma_max_MPa"]) <= s["sigma_max_err_MPa"] + 1e-12 * ref
    assert s["sigma_max_err_MPa"] <= 1e-6 * s["sigma_max_MPa"]


def test_shipped_envelope_config_error_covers_the_true_error():
    # configs/zstk_merko_A_envelope.toml: scheme A (phase 0), every load direction
    s = api.compute(api.load(CONFIGS / "zstk_merko_A_envelope.toml")).summary
    ch = z.close_chain(100.0, 50.0, 6.0, 6.0, s["N"], "outer")
    mats = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    ref = reference_max(ch, mats, 1e4, 0.0, phase=0.0, directions=720)
    assert abs(ref - s["sigma_max_MPa"]) <= s["sigma_max_err_MPa"] + 1e-12 * ref


def random_chains(seed, count):
    """Seeded random chains: R_H 5..200 mm, R_B (0.2..0.8) R_H, e (0..0.9) D, c 1e-9 mm or (0..0.3) D, N the largest
    integer <= N* within 3..20, R_H corrected; Q 1..1e6 N; clearance 0 (twice as likely), +1 % or -0.5 % of the
    smallest roller radius; steel, l 1..50 mm."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        r_h = rng.uniform(5, 200)
        r_b = r_h * rng.uniform(0.2, 0.8)
        d = r_h - r_b
        e, c = d * rng.uniform(0.0, 0.9), d * rng.choice([1e-9, rng.uniform(0, 0.3)])
        n = int(math.floor(z.fractional_roller_number(r_h, r_b, e, c)))
        if not 3 <= n <= 20:
            continue
        ch = z.close_chain(r_h, r_b, e, c, n)
        mats = z.Materials.from_elastic(rng.uniform(1, 50), 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
        r_min = min(z.extreme_roller_radii(ch.outer_radius, ch.inner_radius, ch.eccentricity))
        s = float(rng.choice([0.0, 0.0, 0.01, -0.005])) * r_min
        out.append((ch, mats, 10 ** rng.uniform(0, 6), s))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("case", random_chains(34, 4), ids=lambda c: f"N{c[0].n}")
def test_random_chains_error_covers_the_true_error(case):
    ch, mats, load, clearance = case
    pl = z.critical_placement(ch, mats, load, clearance, tol=1e-6, refine_rtol=1e-5)
    ref = reference_max(ch, mats, load, clearance)
    assert ref - pl.value <= pl.err + 1e-12 * ref   # the reference may find less, never more than the error allows
    assert pl.err <= 1e-6 * pl.value and not pl.phase_sweep.capped
    # the placement reproduces the value
    assert float(z.sigma_max_at(ch, mats, pl.phase, pl.gamma, load, clearance)) == pytest.approx(pl.value, rel=1e-9)


def test_tight_tolerance_ends_with_bounded_work(monkeypatch):
    # issue 34: at tol 1e-11 the fuzz design ran for more than 11 minutes (grids doubled to the cap of 2^16 per
    # turn); the refinement now stops on its value bound.  Work is counted in roller configurations of the joint
    # search's function (measured: about 5 000); the budget of 50 000 stops a regression early.
    ch, mats = fuzz_chain()
    count = [0]
    real = envelope.roller_sigma

    def counting(chain, m, position, relative_direction, *args, **kwargs):
        count[0] += np.broadcast(np.asarray(position), np.asarray(relative_direction)).size
        if count[0] > 50_000:
            raise RuntimeError("over the evaluation budget")
        return real(chain, m, position, relative_direction, *args, **kwargs)

    monkeypatch.setattr(envelope, "roller_sigma", counting)
    pl = z.critical_placement(ch, mats, 563502.5585652901, 0.0, tol=1e-11, refine_rtol=1e-7)
    assert pl.err <= 1e-11 * pl.value and not pl.phase_sweep.capped
    assert count[0] <= 50_000


def test_unreachable_tolerance_stops_and_says_so(monkeypatch):
    # a tolerance below the round-off of the stresses: the refinement reaches the round-off of the angles, the
    # doubling stops at the next level and the sweep is flagged (the report's note), with the error achieved
    ch, mats = fuzz_chain()
    pl = z.critical_placement(ch, mats, 563502.5585652901, 0.0, tol=1e-16, refine_rtol=1e-10)
    assert pl.phase_sweep.capped and pl.phase_sweep.floor
    assert math.isfinite(pl.err) and pl.err > 1e-16 * pl.value
    assert pl.phase_sweep.samples <= 64      # no grid doubling towards the cap

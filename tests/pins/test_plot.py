"""Tests of the ``pins`` calculator's figure (gearcalc.pins.plot; pins.md §8).

Independent references: the crank angle since a pin's entry worked by hand from load-side phases (the loaded arc
[0, psi*] run forwards by the multiplier, backwards by the reducer; phases wrapped into (-180, 180]); a PNG's
signature for the figure itself.
"""
import numpy as np
import pytest

from gearcalc.pins.plot import since_entry

from kinds.test_pins import CONFIGS, FIRST_ORDER, run


def test_since_entry_runs_forward_in_the_multiplier_and_backward_in_the_reducer():
    # loaded phases 5, 20, 60 deg (psi* >= 60): the multiplier entered at 5 (0, 15, 55 deg since), the reducer at 60
    # (55, 40, 0 deg since)
    assert since_entry([5.0, 20.0, 60.0], "multiplier").tolist() == [0.0, 15.0, 55.0]
    assert since_entry([5.0, 20.0, 60.0], "reducer").tolist() == [55.0, 40.0, 0.0]
    assert since_entry([], "reducer").size == 0


def test_a_pin_loaded_just_before_phase_zero_enters_there():
    # the contact level's compliance loads a pin at phase 359.5 deg, i.e. -0.5: it entered first (by hand: 0, 0.5, 30.5)
    got = since_entry(np.array([359.5, 0.0, 30.0]), "multiplier")
    assert got.tolist() == pytest.approx([0.0, 0.5, 30.5], abs=1e-12)
    # (-180, 180]: -180 is the same phase as 180, the interval's closed end, so both pins entered together
    assert since_entry([180.0, -180.0, 170.0], "multiplier").tolist() == [10.0, 10.0, 0.0]


@pytest.mark.slow
def test_plot(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "p.png"
    code, _, err = run(CONFIGS / "pins_paper_cyc_u10_rotating.toml", *FIRST_ORDER, "--plot", out, "--format", "csv")
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    out2 = tmp_path / "f.png"
    code, _, err = run(CONFIGS / "pins_paper_formula_cyc_u10.toml", *FIRST_ORDER, "--plot", out2, "--format", "csv")
    assert code == 0 and out2.stat().st_size > 1000

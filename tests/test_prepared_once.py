"""Each design is prepared once per run: what its check prepared, its computation uses (issue 35 item 2)."""
import gearcalc
from conftest import CONFIGS


def counting(monkeypatch, module, name):
    calls = []
    real = getattr(module, name)

    def spy(*args, **kw):
        calls.append(1)
        return real(*args, **kw)

    monkeypatch.setattr(module, name, spy)
    return calls


def test_zstk_design_is_prepared_once(monkeypatch):
    from gearcalc.zstk import solve

    calls = counting(monkeypatch, solve, "prepare")
    path = CONFIGS / "zstk_merko_A_envelope.toml"  # a direction sweep: computed alone, as in a batch
    once = gearcalc.compute_files([path]).results[0].summary
    assert len(calls) == 1  # the check's arrays serve the computation
    again = gearcalc.compute(gearcalc.load(path)).summary
    assert len(calls) == 2
    assert {k: v for k, v in once.items() if k != "model_time_ms"} == \
        {k: v for k, v in again.items() if k != "model_time_ms"}


def test_pins_contact_design_builds_its_profile_once(monkeypatch):
    from gearcalc.pins import contact_level

    calls = counting(monkeypatch, contact_level, "satellite_profile")
    gearcalc.compute_files([CONFIGS / "pins_paper_circ_u10_fixed.toml"])  # the contact level
    assert len(calls) == 1


def test_a_design_changed_after_its_check_is_prepared_again(monkeypatch):
    from gearcalc.zstk import solve

    path = CONFIGS / "zstk_merko_A_inner.toml"
    d = gearcalc.load(path)
    d.values["load"]["radial_N"] *= 2  # after the check: its prepared arrays no longer fit
    calls = counting(monkeypatch, solve, "prepare")
    changed = gearcalc.compute(d).summary
    assert len(calls) == 1
    fresh = gearcalc.compute(path, overrides={"load.radial_N": d["load.radial_N"]}).summary  # check + compute: 1
    assert {k: v for k, v in changed.items() if k != "model_time_ms"} == \
        {k: v for k, v in fresh.items() if k != "model_time_ms"}
    twice = gearcalc.compute(d).summary  # computed again: prepared again, the same numbers
    assert twice["name"] == changed["name"] and len(calls) == 3

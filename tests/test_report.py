"""gearcalc report: one self-contained HTML page per design or batch (issue 38 item 1).

The page's numbers are checked against the JSON output of `gearcalc run` (the same designs, the same
options); the browser test renders the page in a headless Chromium (skipped when none is on PATH)."""
import json
import re
import shutil
import subprocess
from html.parser import HTMLParser

import pytest

from conftest import CONFIGS, cli

pytest.importorskip("jinja2")


class Cells(HTMLParser):
    """The data-value of each result row and check row, and every script/link/src URL (none allowed)."""

    def __init__(self):
        super().__init__()
        self.fields, self.checks, self.urls = {}, {}, []
        self._row = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "tr":
            self._row = ("field", a["data-field"]) if "data-field" in a else ("check", a["data-check"]) \
                if "data-check" in a else None
        if tag == "td" and "data-value" in a and self._row:
            (self.fields if self._row[0] == "field" else self.checks)[self._row[1]] = json.loads(a["data-value"])
        if tag in ("script", "link", "img", "iframe") or any(k in ("src", "href") and v and "://" in v
                                                              for k, v in attrs):
            self.urls.append((tag, attrs))


def report_and_json(tmp_path, *args):
    out = tmp_path / "calc.html"
    r = cli("report", *args, "-o", out)
    assert r.code == 0, r.err
    j = cli("run", *args, "--format", "json")
    assert j.code == 0
    html = out.read_text(encoding="utf-8")
    p = Cells()
    p.feed(html)
    return html, p, json.loads(j.out)


@pytest.mark.parametrize("config", ["zstk_merko_example.toml", "pins_paper_cyc_u10_fixed.toml",
                                    "rows_fig3_n3_nw3_B2.4.toml", "pins_paper_formula_cyc_u10.toml"])
def test_every_check_and_number_equals_the_json(tmp_path, config):
    key = {"zstk": "load.clearance_mm=0", "pins": "gearing.discs=1", "rows": "rows.cheek_ratio=0.25"}
    setting = "friction.axle=0.1" if "formula" in config else key[config.split("_")[0]]
    html, p, obj = report_and_json(tmp_path, CONFIGS / config, "--set", setting)
    s = obj["summary"]
    margins = {k[len("margin_"):]: v for k, v in s.items() if k.startswith("margin_")}
    assert margins and p.checks == margins          # every check, its margin as the JSON has it
    for key, value in s.items():
        if key.startswith("margin_") or key in ("failed_checks", "name", "model_time_ms") or "_err" in key:
            continue
        if value is None:
            assert key not in p.fields, key           # not computed at this level: left out
        else:
            assert p.fields[key] == value, key       # every result, the JSON's value
    assert obj["name"] in html and obj["file"] in html
    assert ("All checks pass." in html) == (not s["failed_checks"] and any(v is not None for v in margins.values()))
    assert re.search(r">--set<", html)                # the --set key is marked as such
    assert ">file<" in html and (">default<" in html or "formula" in config)  # the formula design gives every key
    assert "<svg" in html and not p.urls              # inline figure, nothing fetched
    assert "References" in html and "Method" in html and "Assumptions" in html


def test_user_strings_are_escaped(tmp_path):
    src = (CONFIGS / "rows_fig3_n3_nw3_B2.4.toml").read_text(encoding="utf-8")
    design = tmp_path / "x.toml"
    design.write_text(re.sub(r'(?m)^name = .*$', 'name = "<script>alert(1)</script> & co"', src), encoding="utf-8")
    out = tmp_path / "r.html"
    r = cli("report", design, "-o", out)
    assert r.code == 0, r.err
    html = out.read_text(encoding="utf-8")
    assert "<script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt; &amp; co" in html


@pytest.mark.slow
def test_batch_one_page_and_bad_design_continues(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('kind = "rows"\n[rows]\ncount = -1\n', encoding="utf-8")
    out = tmp_path / "r.html"
    r = cli("report", CONFIGS / "zstk_merko_example.toml", bad, CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "-o", out)
    assert r.code == 2 and "bad.toml" in r.err
    html = out.read_text(encoding="utf-8")
    assert html.count('<section class="design"') == 2


def test_bad_output_names(tmp_path):
    r = cli("report", CONFIGS / "zstk_merko_example.toml", "-o", tmp_path / "x.txt")
    assert r.code == 2 and "FILE.html or FILE.pdf" in r.err
    r = cli("report", CONFIGS / "zstk_merko_example.toml", "-o", tmp_path / "no" / "x.html")
    assert r.code == 2


def test_pdf_without_a_browser_says_so(tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))       # no chromium on PATH
    r = cli("report", CONFIGS / "zstk_merko_example.toml", "-o", tmp_path / "x.pdf")
    assert r.code == 2 and "Chromium" in r.err and not (tmp_path / "x.pdf").exists()


def png_ink(path) -> float:
    """Fraction of non-white pixels of the screenshot (matplotlib's PNG reader; the test extra has it)."""
    import numpy as np
    from matplotlib.image import imread

    im = imread(str(path))
    assert im.ndim == 3 and im.shape[0] > 100
    return float(np.mean(im[..., :3].min(axis=2) < 0.8))


BROWSER = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)


@pytest.mark.slow
@pytest.mark.skipif(BROWSER is None, reason="no Chromium on PATH (Debian: apt-get install chromium)")
@pytest.mark.parametrize("config", ["zstk_merko_example.toml", "pins_paper_cyc_u10_fixed.toml"])
def test_renders_in_headless_chromium(tmp_path, config):
    out = tmp_path / "calc.html"
    assert cli("report", CONFIGS / config, "-o", out).code == 0
    shot = tmp_path / "shot.png"
    common = [BROWSER, "--headless", "--disable-gpu", "--no-sandbox", f"--user-data-dir={tmp_path / 'profile'}"]
    proc = subprocess.run(common + ["--enable-logging=stderr", "--v=0", f"--screenshot={shot}",
                                    "--window-size=1000,1400", out.as_uri()],
                          capture_output=True, text=True, timeout=240)
    console = [ln for ln in proc.stderr.splitlines() if "CONSOLE" in ln or "Uncaught" in ln]
    assert console == []                              # no console message from the page
    assert shot.exists() and png_ink(shot) > 0.02     # text, tables and figures: not a blank page
    dom = subprocess.run(common + ["--dump-dom", out.as_uri()], capture_output=True, text=True, timeout=240).stdout
    assert "Summary of checks" in dom and "<svg" in dom


@pytest.mark.slow
@pytest.mark.skipif(BROWSER is None, reason="no Chromium on PATH (Debian: apt-get install chromium)")
def test_pdf_through_chromium(tmp_path):
    out = tmp_path / "calc.pdf"
    r = cli("report", CONFIGS / "zstk_merko_example.toml", "-o", out)
    assert r.code == 0, r.err
    assert out.read_bytes()[:5] == b"%PDF-" and out.stat().st_size > 20_000


def test_without_matplotlib_the_page_says_figures_need_the_plot_extra(monkeypatch):
    import sys

    from gearcalc.report import FIGURE_HINT, figures_of

    monkeypatch.setitem(sys.modules, "matplotlib", None)   # import matplotlib raises ImportError
    assert figures_of([object()]) == ({}, FIGURE_HINT)
    assert "gearcalc[plot]" in FIGURE_HINT

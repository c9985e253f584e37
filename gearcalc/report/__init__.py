"""``gearcalc report FILE... -o calc.html``: one self-contained calculation report (HTML, or PDF through a
headless Chromium).

jinja2 is imported here only, and this package only by the ``report`` command.  Every user string reaches the
page through jinja2's autoescaping; the figures are the kinds' ``--plot`` figures rendered to SVG in memory and
inlined (matplotlib optional: without it the report says the figures need the ``plot`` extra).  The page loads
nothing from the network (no scripts, no fonts, no images by URL).
"""
from __future__ import annotations

import datetime as _dt
import hashlib
import os
import re
from dataclasses import dataclass, field
from typing import Any

from .method import ASSUMPTIONS, CHECKS, REFERENCES, method_lines

FIGURE_HINT = "figures need the plot extra: pip install 'gearcalc[plot]'"
"""What the report says in place of the figures when matplotlib is absent."""


@dataclass
class Page:
    """One design's section of the report."""

    rec: Any
    file: str
    sha256: str
    inputs: list = field(default_factory=list)
    checks: list = field(default_factory=list)
    method: list = field(default_factory=list)
    results: list = field(default_factory=list)
    figures: list = field(default_factory=list)


def file_hash(source: str) -> str:
    """SHA-256 of the design file's bytes ("" for standard input)."""
    if source == "-" or not os.path.isfile(source):
        return ""
    with open(source, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def fmt(v: Any) -> str:
    """A value as the report shows it: 6 significant digits, true/false, — for none."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(fmt(x) for x in v)
    return str(v)


def inputs_of(design, set_keys: set) -> list[tuple[str, str, str, str]]:
    """(dotted key, value, unit, source) for every resolved design key; source: --set, file or default."""
    from ..units import split_unit

    rows = []
    for table, vals in design.resolved().items():
        if not isinstance(vals, dict):
            continue
        for key, value in vals.items():
            dotted = f"{table}.{key}"
            src = "--set" if dotted in set_keys else "file" if design.is_given(dotted) else "default"
            rows.append((dotted, fmt(value), split_unit(key)[1], src))
    return rows


def checks_of(rec) -> list[dict]:
    """Every check of the summary (its ``margin_*`` fields): value, allowable, margin, PASS/FAIL."""
    s = rec.result.summary
    failed = set(s.get("failed_checks") or ()) | set(rec.result.failed)
    out = []
    for key in s:
        if not key.startswith("margin_"):
            continue
        name = key[len("margin_"):]
        value_key, allow_key, text = CHECKS.get((rec.kind, name), (None, None, name.replace("_", " ")))
        margin = s[key]
        status = "FAIL" if name in failed or (margin is not None and margin < 0) else (
            "not checked" if margin is None else "PASS")
        shown = value_key and margin is not None  # a check that does not apply shows no value
        out.append({"name": name, "text": text, "value": fmt(s.get(value_key)) if shown else "—",
                    "allowable": fmt(s.get(allow_key)) if allow_key else "—", "margin": fmt(margin),
                    "exact": exact(margin), "status": status})
    return out


def results_of(rec) -> list[tuple[str, str, str, str]]:
    """(field, value, stated error, unit) of every summary field that is not a margin or an error."""
    from ..units import split_unit

    s = rec.result.summary
    rows = []
    for key, value in s.items():
        if key.startswith("margin_") or key == "failed_checks" or key == "name" or value is None:
            continue  # a field the design's model level does not compute is left out
        base, unit = split_unit(key)
        if base.endswith("_err"):
            continue
        err_key = f"{base}_err_{unit}" if unit else f"{base}_err"
        rows.append((key, fmt(value), fmt(s[err_key]) if err_key in s else "", unit, exact(value)))
    return rows


def exact(value: Any) -> str:
    """The value as the JSON output writes it (the cells' ``data-value``: the page's numbers, checkable)."""
    import json

    from ..render import plain

    return json.dumps(plain(value), ensure_ascii=False)


def figures_of(recs) -> tuple[dict, str]:
    """({id(record): [svg text, ...]}, note): each design's figure from its kind's plot hook, as inline SVG."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return {}, FIGURE_HINT
    import io

    from .. import plot as gplot
    from .. import registry

    out: dict = {}
    plt = gplot._pyplot()
    for rec in recs:
        calc = registry.get(rec.kind)
        if calc.plot is None:
            continue
        gplot._collected = []
        try:
            calc.plot([rec], "figure.svg")
            figs = list(gplot._collected)
        finally:
            gplot._collected = None
        svgs = []
        for fig in figs:
            buf = io.StringIO()
            fig.savefig(buf, format="svg")
            plt.close(fig)
            text = buf.getvalue()
            text = text[text.index("<svg"):]  # no XML declaration nor DOCTYPE inside HTML
            svgs.append(re.sub(r'<svg ([^>]*?)width="[^"]*" height="[^"]*"', r'<svg \1', text, count=1))
        out[id(rec)] = svgs
    return out, ""


def build(records, designs, set_keys: set, tol: float, model: str | None, now: _dt.datetime | None = None) -> str:
    """The HTML of the report of ``records`` (``designs``: the loaded designs, matched by source and name)."""
    import jinja2

    from .. import __version__
    from ..design import display_name

    by_key = {(d.source, d.name): d for d in designs}
    figures, figure_note = figures_of(records)
    pages = []
    for rec in records:
        d = by_key.get((rec.source, rec.name))
        pages.append(Page(rec=rec, file=display_name(rec.source), sha256=file_hash(rec.source),
                          inputs=inputs_of(d, set_keys) if d else [], checks=checks_of(rec),
                          method=method_lines(rec), results=results_of(rec), figures=figures.get(id(rec), [])))
    if now is None:
        epoch = os.environ.get("SOURCE_DATE_EPOCH")
        now = (_dt.datetime.fromtimestamp(int(epoch), _dt.timezone.utc) if epoch and epoch.isdigit()
               else _dt.datetime.now(_dt.timezone.utc))
    env = jinja2.Environment(loader=jinja2.PackageLoader("gearcalc.report", "templates"),
                             autoescape=True, undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True)
    env.filters["fmt"] = fmt
    return env.get_template("report.html.j2").render(
        pages=pages, version=__version__, date=now.strftime("%Y-%m-%d %H:%M UTC"), tol=tol, model=model,
        assumptions=ASSUMPTIONS, references=REFERENCES, figure_note=figure_note,
        markup=jinja2.utils.markupsafe.Markup)


PDF_BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
"""Browsers tried, in order, for ``-o FILE.pdf`` (headless --print-to-pdf)."""


def browser() -> str | None:
    """The first of :data:`PDF_BROWSERS` on PATH, or None."""
    import shutil

    return next((p for p in map(shutil.which, PDF_BROWSERS) if p), None)


def html_to_pdf(html: str, exe: str) -> bytes:
    """Print the page to PDF with a headless Chromium (in a temporary directory of ours); OSError on failure."""
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory(prefix="gearcalc-report-") as tmp:
        src, pdf = os.path.join(tmp, "report.html"), os.path.join(tmp, "report.pdf")
        with open(src, "w", encoding="utf-8") as f:
            f.write(html)
        proc = subprocess.run([exe, "--headless", "--disable-gpu", "--no-sandbox", f"--user-data-dir={tmp}/profile",
                               "--no-pdf-header-footer", f"--print-to-pdf={pdf}", "file://" + src],
                              capture_output=True, timeout=300, check=False)
        if not os.path.isfile(pdf):
            raise OSError(f"{os.path.basename(exe)} did not write the PDF (exit {proc.returncode})")
        with open(pdf, "rb") as f:
            return f.read()

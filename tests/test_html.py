"""HTML tables with units for notebooks (issue 38 item 5): ``_repr_html_`` of Result, Batch and Columns."""
from __future__ import annotations

import math
from html.parser import HTMLParser

import gearcalc
from conftest import CONFIGS
from gearcalc.calculator import Result
from gearcalc.render import Columns, html_header
from gearcalc.units import split_unit

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
ZSTK = CONFIGS / "zstk_merko_example.toml"


class Cells(HTMLParser):
    """The rows of a table: each a list of (tag, text, attributes) cells; header cells too."""

    def __init__(self):
        super().__init__()
        self.rows, self.cell, self.paragraphs, self.in_p = [], None, [], False

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self.cell = [tag, "", dict(attrs)]
        elif tag == "p":
            self.in_p = True
            self.paragraphs.append("")

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.rows[-1].append(tuple(self.cell))
            self.cell = None
        elif tag == "p":
            self.in_p = False

    def handle_data(self, data):
        if self.cell is not None:
            self.cell[1] += data
        elif self.in_p:
            self.paragraphs[-1] += data


def parse(text: str) -> Cells:
    p = Cells()
    p.feed(text)
    return p


def same(cell, value) -> bool:
    """A cell shows the value: a float exactly in its title (the text has 6 digits), others as the table does."""
    tag, text, attrs = cell
    if isinstance(value, float):
        return float(attrs["title"]) == value or (math.isnan(value) and math.isnan(float(attrs["title"])))
    if isinstance(value, bool):
        return text == ("yes" if value else "no")
    if isinstance(value, int):
        return int(text) == value
    if value is None:
        return text == "n/a" or text  # n/a, or the result's label for it (e.g. "self-locking")
    if isinstance(value, list):
        return text == (" ".join(str(v) for v in value) or "-")
    return text == str(value)


def test_a_result_is_a_table_of_every_summary_field_with_its_unit():
    r = gearcalc.compute(FIG3)
    rows = parse(r._repr_html_()).rows[1:]  # after the header row
    assert [row[0][1] for row in rows] == [split_unit(k)[0] for k in r.summary]
    for (name, value), row in zip(r.summary.items(), rows):
        assert same(row[1], value), (name, row, value)
        assert row[2][1] == split_unit(name)[1]  # the unit column: from the field's suffix
    assert any(row[2][1] == "N/mm" for row in rows)


def test_a_batch_has_a_column_per_field_with_units_in_the_titles():
    b = gearcalc.compute_files([FIG3, ZSTK])
    parsed = parse(b._repr_html_())
    header = [c[1] for c in parsed.rows[0]]
    assert header[0] == "kind" and "sigma_max [MPa]" in header and "w_mean [N/mm]" in header
    assert len(parsed.rows) == 1 + len(b.records)
    names = ["kind"] + [n for n in dict.fromkeys(k for r in b.records for k in r.result.summary)]
    assert header == [html_header(n) for n in names]
    for rec, row in zip(b.records, parsed.rows[1:]):
        for name, cell in zip(names, row):
            if name == "kind":
                assert cell[1] == rec.kind
            elif name in rec.result.summary:
                assert same(cell, rec.result.summary[name]), (name, cell)
            else:
                assert cell[1] == "n/a"  # a field of the other kind


def test_columns_of_a_sweep_render_with_units_and_errors():
    parts = list(gearcalc.sweep(FIG3, {"rows.count": [3, 4]}))
    cols = parts[0].lists()
    parsed = parse(cols._repr_html_())
    header = [c[1] for c in parsed.rows[0]]
    assert header == [html_header(n) for n in cols.data] and "w_max [N/mm]" in header
    for k, row in enumerate(parsed.rows[1:]):
        for name, cell in zip(cols.data, row):
            assert same(cell, cols.data[name][k]), (name, cell)


def test_text_is_escaped_and_long_columns_are_cut():
    r = Result(summary={"name": "<b>&</b>", "x_mm": 1.5}, kind="rows")
    text = r._repr_html_()
    assert "<b>" not in text and parse(text).rows[1][1][1] == "<b>&</b>"
    cols = Columns({"x_mm": [float(k) for k in range(1200)]}, ["at {'a': 1}: <oops>"])
    parsed = parse(cols._repr_html_())
    assert len(parsed.rows) == 1 + 500 and parsed.rows[0][0][1] == "x [mm]"
    assert parsed.paragraphs[0].startswith("… 700 more rows") and parsed.paragraphs[1] == "at {'a': 1}: <oops>"

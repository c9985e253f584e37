"""gearcalc.explore.designfile: a design's text with new values (comments kept), and one file per point.

Expected values: the TOML read back (tomllib) and the files on disk; never-clobber per interface.md.
"""
import tomllib
from pathlib import Path

import pytest

from gearcalc.explore.designfile import save_designs, with_values

TEXT = """# a design
kind = "rows"

[rows]
count = 3        # rows of pins
module_mm = 2.0

[sun]
torque_Nm = 10.0 # input
"""


def test_with_values_keeps_comments_and_sets_each_key():
    out = with_values(TEXT, {"rows.count": 4, "sun.torque_Nm": 12.5, "sun.speed_rpm": 1500.0, "new.x": True})
    assert "# a design" in out and "count = 4        # rows of pins" in out and "torque_Nm = 12.5 # input" in out
    data = tomllib.loads(out)
    assert data["rows"] == {"count": 4, "module_mm": 2.0}
    assert data["sun"] == {"torque_Nm": 12.5, "speed_rpm": 1500.0} and data["new"] == {"x": True}


def test_with_values_gives_up_on_keys_it_cannot_place():
    # an inline table: the key is not spelt as key = value under a [table] header
    assert with_values('kind = "rows"\nrows = {count = 3}\n', {"rows.count": 4}) is None


def test_save_designs_writes_one_file_per_point_and_never_clobbers(tmp_path):
    src = tmp_path / "d.toml"
    src.write_text(TEXT)
    out = tmp_path / "out"
    paths = save_designs(str(out), str(src), tomllib.loads(TEXT), [{"rows.count": 4}, {"rows.count": 5}])
    assert [p.rsplit("/", 1)[1] for p in paths] == ["d_opt_001.toml", "d_opt_002.toml"]
    assert [tomllib.loads(Path(p).read_text())["rows"]["count"] for p in paths] == [4, 5]
    assert "# rows of pins" in Path(paths[0]).read_text()
    with pytest.raises(FileExistsError):
        save_designs(str(out), str(src), tomllib.loads(TEXT), [{"rows.count": 6}, {"rows.count": 7}])
    assert sorted(p.name for p in out.iterdir()) == ["d_opt_001.toml", "d_opt_002.toml"]   # nothing written
    one = save_designs(str(out), "-", tomllib.loads(TEXT), [{"rows.count": 9}])              # stdin: no text
    assert one[0].endswith("design_opt.toml") and tomllib.loads(Path(one[0]).read_text())["rows"]["count"] == 9

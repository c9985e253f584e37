"""gearcalc.arrays: unique_sorted equals numpy.unique on the arrays the calculators pass it."""
import subprocess
import sys

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from gearcalc.arrays import unique_sorted


@settings(max_examples=200, deadline=None, derandomize=True)
@given(arrays(np.float64, st.integers(0, 40), elements=st.floats(-1e6, 1e6, allow_nan=False)))
def test_unique_sorted_equals_numpy_unique(a):
    np.testing.assert_array_equal(unique_sorted(a), np.unique(a))


@settings(max_examples=100, deadline=None, derandomize=True)
@given(st.lists(st.integers(-5, 5), max_size=30))
def test_unique_sorted_on_integers(values):
    assert unique_sorted(values).tolist() == sorted(set(values))


def test_one_design_does_not_import_numpy_ma(tmp_path):
    # numpy.unique would import numpy.ma (~8 ms of start-up) on the one-design path
    code = ("import sys; from gearcalc.cli import main; sys.argv = ['gearcalc', 'run', '{}', '{}', '{}', "
            "'-f', 'csv', '-o', '{}'];\ntry:\n    main()\nexcept SystemExit:\n    pass\n"
            "assert 'numpy.ma' not in sys.modules, 'numpy.ma imported'")
    from conftest import CONFIGS

    files = [CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", CONFIGS / "zstk_merko_example.toml",
             CONFIGS / "pins_paper_cyc_u10_fixed.toml"]
    r = subprocess.run([sys.executable, "-c", code.format(*files, tmp_path / "out.csv")], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr[-500:]

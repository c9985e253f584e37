"""The build backend: setuptools' own (``setuptools.build_meta``), with the man page in editable installs too.

``[tool.setuptools.data-files]`` installs man/gearcalc.1 as <prefix>/share/man/man1/gearcalc.1, where
``man gearcalc`` finds it (man-db looks in <dir>/../share/man for each <dir> on PATH).  Wheels and sdists
carry it; but setuptools' editable wheel (``pip install -e .``, the README's developer install) asks the
distribution for ``has_data``, which it does not have (it has ``has_data_files``), so it installs no data
files.  This module gives the distribution that method before an editable build and changes nothing else;
when setuptools has the method itself, nothing at all.
"""
from setuptools import build_meta as _meta
from setuptools.build_meta import *  # noqa: F401,F403 - the PEP 517 hooks, unchanged
from setuptools.build_meta import __all__  # noqa: F401


def data_in_editable() -> None:
    """Make setuptools' editable wheel install the data files (the man page), as its wheel does."""
    from setuptools.dist import Distribution

    if not hasattr(Distribution, "has_data"):
        Distribution.has_data = Distribution.has_data_files


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    data_in_editable()
    return _meta.build_editable(wheel_directory, config_settings, metadata_directory)

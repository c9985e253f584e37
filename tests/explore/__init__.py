"""Tests of gearcalc.explore (tests/explore/test_<module>.py mirrors gearcalc/explore/<module>.py)."""

"""Tests of gearcalc.kinds (tests/kinds/test_<module>.py mirrors gearcalc/kinds/<module>.py)."""

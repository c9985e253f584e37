"""Tests of gearcalc.rows (tests/rows/test_<module>.py mirrors gearcalc/rows/<module>.py)."""
